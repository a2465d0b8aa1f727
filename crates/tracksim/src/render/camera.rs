//! Pinhole cameras: [`Intrinsics`] (size and horizontal field of view, square pixels), their
//! pose ([`CameraPose`], REP 103: the camera looks along its x axis, y left, z up) and the
//! chase camera ([`ChaseCamera`]): behind and above a robot, following its heading only (not
//! its roll or pitch), for learners' frames and videos.
//!
//! Pixel (u, v), column u from the left and row v from the top, looks along
//! `(1, -(u + 0.5 - W/2) / f, -(v + 0.5 - H/2) / f)` in the camera frame, with the focal length
//! `f = (W / 2) / tan(hfov / 2)` pixels: the x component is 1, so a ray's time of impact is the
//! depth along the optical axis. The same rays as the depth camera.

use glam::{DMat3, DQuat, DVec3};

/// A pinhole camera's image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Horizontal field of view, rad (0..pi).
    pub horizontal_fov: f64,
}

impl Intrinsics {
    /// Focal length, pixels.
    pub fn focal_px(&self) -> f64 {
        self.width as f64 / 2.0 / (self.horizontal_fov / 2.0).tan()
    }

    /// Vertical field of view, rad.
    pub fn vertical_fov(&self) -> f64 {
        2.0 * (self.height as f64 / 2.0 / self.focal_px()).atan()
    }

    /// How far the image's corner ray reaches per metre of depth (>= 1): a camera that sees
    /// `d` m of depth needs the scene within `d * corner_factor()` m.
    pub fn corner_factor(&self) -> f64 {
        let (w, h) = (self.width as f64, self.height as f64);
        (1.0 + (w * w + h * h) / (4.0 * self.focal_px().powi(2))).sqrt()
    }

    /// The ray of every pixel in the camera frame (x = 1), row by row from the top.
    pub fn pixel_rays(&self) -> Vec<DVec3> {
        let f = self.focal_px();
        let (w, h) = (self.width as f64, self.height as f64);
        (0..self.height)
            .flat_map(|v| {
                (0..self.width).map(move |u| {
                    DVec3::new(
                        1.0,
                        -(u as f64 + 0.5 - w / 2.0) / f,
                        -(v as f64 + 0.5 - h / 2.0) / f,
                    )
                })
            })
            .collect()
    }

    /// [`Self::pixel_rays`] in single precision (what [`super::render`] takes).
    pub fn pixel_rays_f32(&self) -> Vec<glam::Vec3> {
        self.pixel_rays().iter().map(|d| d.as_vec3()).collect()
    }

    /// ROS's camera matrix K (row-major 3 x 3) in the optical frame (z forward, x right,
    /// y down): `[f 0 cx; 0 f cy; 0 0 1]` with the principal point at the image centre.
    pub fn k_matrix(&self) -> [f64; 9] {
        let f = self.focal_px();
        let (cx, cy) = (self.width as f64 / 2.0, self.height as f64 / 2.0);
        [f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0]
    }
}

/// Where a camera is: position (m) and orientation of its frame, in the frame the scene is
/// given in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    /// Position, m.
    pub position: DVec3,
    /// Orientation: camera frame to scene frame.
    pub rotation: DQuat,
}

impl CameraPose {
    /// A camera at `eye` looking at `target`, its z axis as near to +z as the view allows.
    pub fn look_at(eye: DVec3, target: DVec3) -> CameraPose {
        let x = (target - eye).try_normalize().unwrap_or(DVec3::X);
        let y = DVec3::Z.cross(x).try_normalize().unwrap_or(DVec3::Y);
        let z = x.cross(y);
        CameraPose {
            position: eye,
            rotation: DQuat::from_mat3(&DMat3::from_cols(x, y, z)).normalize(),
        }
    }
}

/// A camera behind and above a robot, turning with its heading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChaseCamera {
    /// Distance behind the robot's body origin, horizontally, m.
    pub behind: f64,
    /// Height above the body origin, m.
    pub above: f64,
    /// The point looked at, ahead of the body origin along its heading, m.
    pub look_ahead: f64,
    /// The image.
    pub intrinsics: Intrinsics,
}

impl Default for ChaseCamera {
    fn default() -> Self {
        ChaseCamera {
            behind: 1.6,
            above: 0.9,
            look_ahead: 0.4,
            intrinsics: Intrinsics {
                width: 160,
                height: 120,
                horizontal_fov: 70f64.to_radians(),
            },
        }
    }
}

impl ChaseCamera {
    /// The camera's pose for a body at `position` with orientation `rotation`.
    pub fn pose(&self, position: DVec3, rotation: DQuat) -> CameraPose {
        let fwd = rotation * DVec3::X;
        let heading = DVec3::new(fwd.x, fwd.y, 0.0)
            .try_normalize()
            .unwrap_or(DVec3::X);
        let eye = position - heading * self.behind + DVec3::Z * self.above;
        CameraPose::look_at(eye, position + heading * self.look_ahead)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_points_x_at_the_target_and_keeps_z_up() {
        let p = CameraPose::look_at(DVec3::new(-2.0, 0.0, 1.0), DVec3::new(0.0, 0.0, 0.0));
        let x = p.rotation * DVec3::X;
        assert!((x - DVec3::new(2.0, 0.0, -1.0).normalize()).length() < 1e-12);
        assert!((p.rotation * DVec3::Y - DVec3::Y).length() < 1e-12);
        assert!((p.rotation * DVec3::Z).z > 0.0);
    }

    #[test]
    fn centre_pixels_straddle_the_axis() {
        let i = Intrinsics {
            width: 4,
            height: 2,
            horizontal_fov: std::f64::consts::FRAC_PI_2,
        };
        assert!((i.focal_px() - 2.0).abs() < 1e-12);
        let r = i.pixel_rays();
        assert!((r[1] - DVec3::new(1.0, 0.25, 0.25)).length() < 1e-12);
        assert!((r[6] - DVec3::new(1.0, -0.25, -0.25)).length() < 1e-12);
    }
}
