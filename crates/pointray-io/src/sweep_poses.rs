//! Sensor poses of a sequence of sweeps: where each sweep's sensor frame sits in the map.
//!
//! A poses file holds one pose a line, either KITTI's 3x4 row-major matrix (12 numbers) or a
//! whole 4x4 one (16 numbers); blank lines and lines starting with `#` are skipped. A sweep
//! takes the pose of its place in the file when the file holds one pose per sweep given, and
//! otherwise the pose its file name numbers (`000002.bin` and `scan02.bin` take line 2, from 0).

use std::path::Path;

use glam::{DAffine3, DMat3, DVec3};

use crate::IoError;

/// A rotation's columns may stray this far from unit length and from each other before the
/// matrix is refused as not a rigid pose.
const RIGID_TOLERANCE: f64 = 1e-3;

/// The poses of a sequence, in the file's order.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoses {
    pub poses: Vec<DAffine3>,
}

impl SweepPoses {
    pub fn read(path: &Path) -> Result<Self, IoError> {
        let text = std::fs::read_to_string(path).map_err(|source| IoError::os(path, source))?;
        Self::parse(&text).map_err(|problem| IoError::malformed(path, problem))
    }

    pub fn parse(text: &str) -> Result<Self, String> {
        let poses = text
            .lines()
            .enumerate()
            .filter(|(_, line)| !line.trim().is_empty() && !line.trim_start().starts_with('#'))
            .map(|(index, line)| {
                pose_of_line(line).map_err(|problem| format!("line {}: {problem}", index + 1))
            })
            .collect::<Result<Vec<_>, _>>()?;
        if poses.is_empty() {
            return Err("holds no poses".into());
        }
        Ok(Self { poses })
    }

    /// The pose of each of `sweeps`: in order when the file holds one for each, else by the
    /// number in each sweep's file name.
    pub fn for_sweeps(
        &self,
        sweeps: &[impl AsRef<Path>],
        poses_file: &Path,
    ) -> Result<Vec<DAffine3>, IoError> {
        if self.poses.len() == sweeps.len() {
            return Ok(self.poses.clone());
        }
        sweeps
            .iter()
            .map(|sweep| {
                let sweep = sweep.as_ref();
                let index = frame_number(sweep).ok_or_else(|| {
                    IoError::malformed(
                        poses_file,
                        format!(
                            "holds {} poses for {} sweeps, and {} names no frame number to pick its pose by",
                            self.poses.len(),
                            sweeps.len(),
                            sweep.display()
                        ),
                    )
                })?;
                self.poses.get(index).copied().ok_or_else(|| {
                    IoError::malformed(
                        poses_file,
                        format!("holds {} poses; {} needs pose {index}", self.poses.len(), sweep.display()),
                    )
                })
            })
            .collect()
    }
}

fn pose_of_line(line: &str) -> Result<DAffine3, String> {
    let numbers: Vec<f64> = line
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|word| !word.is_empty())
        .map(|word| word.parse::<f64>().map_err(|_| format!("{word:?} is not a number")))
        .collect::<Result<_, _>>()?;
    if !matches!(numbers.len(), 12 | 16) {
        return Err(format!("{} numbers; a pose is 12 (3x4, row-major) or 16 (4x4)", numbers.len()));
    }
    if numbers.iter().any(|n| !n.is_finite()) {
        return Err("a pose must be finite".into());
    }
    if numbers.len() == 16 && numbers[12..] != [0.0, 0.0, 0.0, 1.0] {
        return Err("the last row of a 4x4 pose must be 0 0 0 1".into());
    }
    let row = |r: usize| DVec3::new(numbers[4 * r], numbers[4 * r + 1], numbers[4 * r + 2]);
    let rotation = DMat3::from_cols(row(0), row(1), row(2)).transpose();
    if !is_rigid(rotation) {
        return Err("the 3x3 part is not a rotation".into());
    }
    Ok(DAffine3::from_mat3_translation(rotation, DVec3::new(numbers[3], numbers[7], numbers[11])))
}

fn is_rigid(rotation: DMat3) -> bool {
    let gram = rotation.transpose() * rotation;
    gram.abs_diff_eq(DMat3::IDENTITY, RIGID_TOLERANCE) && rotation.determinant() > 0.0
}

/// The last run of digits in a file's stem: `000002` gives 2, `scan02` gives 2.
fn frame_number(path: &Path) -> Option<usize> {
    let stem = path.file_name()?.to_str()?.split('.').next()?;
    let digits: String = stem.chars().rev().take_while(char::is_ascii_digit).collect();
    digits.chars().rev().collect::<String>().parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    const KITTI: &str = "1 0 0 0 0 1 0 0 0 0 1 0\n\n# moved\n1 0 0 0.5 0 1 0 -1 0 0 1 2\n";

    #[test]
    fn kitti_lines_read_as_rigid_poses() {
        let poses = SweepPoses::parse(KITTI).unwrap();
        assert_eq!(poses.poses.len(), 2);
        assert_eq!(poses.poses[1].transform_point3(DVec3::ZERO), DVec3::new(0.5, -1.0, 2.0));
    }

    #[test]
    fn four_by_four_poses_read_too_and_bad_ones_name_their_line() {
        let poses = SweepPoses::parse("0 -1 0 1  1 0 0 2  0 0 1 3  0 0 0 1").unwrap();
        assert_eq!(poses.poses[0].transform_vector3(DVec3::X), DVec3::Y);
        let sheared = SweepPoses::parse("1 0 0 0 0 1 0 0 0 0 1 0\n1 1 0 0 0 1 0 0 0 0 1 0").unwrap_err();
        assert!(sheared.contains("line 2"), "{sheared}");
        assert!(SweepPoses::parse("1 2 3").unwrap_err().contains("3 numbers"));
        assert!(SweepPoses::parse("").is_err());
    }

    #[test]
    fn sweeps_take_poses_in_order_or_by_their_frame_number() {
        let poses = SweepPoses::parse(&KITTI.repeat(2)).unwrap();
        let by_name = poses.for_sweeps(&["a/scan03.bin", "a/000001.bin"], Path::new("p.txt")).unwrap();
        assert_eq!(by_name, vec![poses.poses[3], poses.poses[1]]);
        assert!(poses.for_sweeps(&["a/scan09.bin"], Path::new("p.txt")).is_err());
        assert!(poses.for_sweeps(&["a/first.bin"], Path::new("p.txt")).is_err());
    }
}
