//! How the programs' edges (the command line and the Python module) report an error.

use std::error::Error;

/// The error and its causes on one line. Our library errors already quote their source in
/// their own message, so a cause is only added when its text is not there yet.
pub fn error_line(error: &(dyn Error + 'static)) -> String {
    let mut text = String::new();
    let mut cause = Some(error);
    while let Some(current) = cause {
        let message = current.to_string();
        if !text.contains(&message) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&message);
        }
        cause = current.source();
    }
    text
}
