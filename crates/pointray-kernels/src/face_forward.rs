//! Turning a normal toward the viewer. Twin of `shaders/face_forward.glsl`.

use glam::Vec3;

/// `normal`, flipped if it points along `ray_direction` (away from the ray's origin).
pub fn face_forward(normal: Vec3, ray_direction: Vec3) -> Vec3 {
    if normal.dot(ray_direction) > 0.0 { -normal } else { normal }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_facing_the_ray_origin_is_kept_and_one_facing_away_is_flipped() {
        let toward_camera = Vec3::new(0.0, 1.0, 1.0).normalize();
        assert_eq!(face_forward(toward_camera, Vec3::NEG_Z), toward_camera);
        assert_eq!(face_forward(-toward_camera, Vec3::NEG_Z), toward_camera);
    }
}
