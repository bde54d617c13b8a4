#pragma once
/// Moving the camera with the mouse and keys: pure functions on CameraParams
/// (no GL, no ImGui), so the 3D view and tests share them.
/// Orbit keeps `up` as the world's up direction; the camera never rolls.

#include <string>

#include "core/math/aabb.h"
#include "core/render/camera.h"

namespace accelviz {

/// Turns the eye around the target: `yaw` radians about `up`, then `pitch`
/// radians about the camera's right axis (positive: the eye rises). The eye stays
/// at least 1 degree away from straight above or below the target.
void orbit(CameraParams& camera, double yaw, double pitch);

/// Slides eye and target together in the image plane. dx, dy are fractions of the
/// view's height (as a mouse drag is in pixels / view height): dragging by the full
/// height moves the scene by the height of the view at the target's distance.
/// Positive dx moves the scene right, positive dy moves it up.
void pan(CameraParams& camera, double dx, double dy);

/// Moves the eye towards (factor < 1) or away from (factor > 1) the target.
void dolly(CameraParams& camera, double factor);

/// Keeps the viewing direction, aims at the centre of `bounds`, and moves the eye
/// so the bounds' enclosing sphere fits the view (aspect = width / height).
void frame_bounds(CameraParams& camera, const Aabb& bounds, double aspect);

/// "--eye x,y,z --target x,y,z --up x,y,z --fov f": the CLI flags that reproduce
/// this camera with `accelviz render`.
std::string camera_cli_flags(const CameraParams& camera);

}  // namespace accelviz
