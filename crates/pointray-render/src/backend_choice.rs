//! Which renderer a program asked for: the Vulkan ray tracer, the CPU renderer, or the first
//! that suits (`Auto`). `Backend::open` is the one place a choice becomes a renderer.

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BackendChoice {
    /// A hardware ray-tracing GPU if there is one, otherwise the CPU renderer.
    #[default]
    Auto,
    Vulkan,
    Cpu,
}

impl BackendChoice {
    /// The names command lines use, in order.
    pub const NAMES: [&'static str; 3] = ["auto", "vulkan", "cpu"];
}

impl std::str::FromStr for BackendChoice {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "auto" => Ok(Self::Auto),
            "vulkan" => Ok(Self::Vulkan),
            "cpu" => Ok(Self::Cpu),
            other => Err(format!("unknown backend `{other}` (expected auto, vulkan or cpu)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses() {
        let parsed: Vec<BackendChoice> = BackendChoice::NAMES.iter().map(|n| n.parse().unwrap()).collect();
        assert_eq!(parsed, [BackendChoice::Auto, BackendChoice::Vulkan, BackendChoice::Cpu]);
        assert!("gpu".parse::<BackendChoice>().is_err());
    }
}
