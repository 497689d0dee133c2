use glam::Vec3;

/// The camera as a scene describes it (DTU `Camera::set`): where it is, what it looks at, which
/// way is up, and the focal distance `d` from the eye to the image plane, measured in units of
/// the image plane's height (so the vertical field of view is `2·atan(1/(2d))`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSetup {
    /// Eye point `e`.
    pub eye: Vec3,
    /// Point the camera looks at, `p`.
    pub look_at: Vec3,
    /// Up vector `u` (need not be perpendicular to the view direction).
    pub up: Vec3,
    /// Focal distance `d`, in image-plane heights.
    pub focal_distance: f32,
}
