// From a scene camera and an image size to the device's CameraData.
#pragma once

#include <cstdint>
#include <string>

#include "scene/scene.h"
#include "shared/render_types.h"

namespace clpt {

// The camera to render with: `spec` is empty (the file's first camera, else a default
// camera framing the scene), an index, or a camera name. Throws Error(Usage) if not found.
Camera choose_camera(const Scene& scene, const std::string& spec);

// The image size when the user gives none: 640 pixels wide, the height from the camera's
// aspect ratio (4:3 when the file gives none).
void default_resolution(const Camera& camera, uint32_t* width, uint32_t* height);

// The vertical field of view is kept; the horizontal one follows the image's aspect ratio.
dev::CameraData camera_data(const Camera& camera, uint32_t width, uint32_t height);

// Makes the camera a thin lens of the given aperture radius, in focus at focus_distance along
// the view (0: at the centre of `bounds`, projected on the view direction; if that is behind
// the camera, at the bounding sphere's radius). aperture 0 keeps a pinhole.
void set_thin_lens(dev::CameraData& camera, float aperture, float focus_distance,
                   const Bounds& bounds);

// The side of one pixel's footprint on a plane facing the camera at the centre of `bounds`
// (its depth along the view; if that is not ahead, half the bounds' diagonal): for SPPM's
// default initial radius. Orthographic cameras: the pixel's side.
float pixel_footprint(const dev::CameraData& camera, uint32_t height, const Bounds& bounds);

}  // namespace clpt
