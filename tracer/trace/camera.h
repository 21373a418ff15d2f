/* camera.h — pinhole primary rays from a view.
 *
 * Convention (../shared/scenes/README.md, "Camera convention"):
 *   forward = normalize(at - eye); right = normalize(cross(forward, up));
 *   up' = cross(right, forward); s = tan(fov/2);
 *   pixel (px, py), py = 0 is the top row, image W x H:
 *     u = (2*(px + 0.5)/W - 1) * s * W/H,  v = (1 - 2*(py + 0.5)/H) * s
 *     dir = normalize(forward + u*right + v*up')
 * Primary rays: org = eye, unit dir, tmin = 0, tmax = FLT_MAX (RT_RAY_TMAX),
 * pixel = py*W + px, bounce = 0. Arithmetic in double, rounded to float at the
 * end, so results are deterministic. Default resolution 1280x720 (the paper's). */
#ifndef RTSIM_TRACER_CAMERA_H
#define RTSIM_TRACER_CAMERA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/trace/ray.h"
#include "tracer/io/view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_DEFAULT_WIDTH 1280
#define RT_DEFAULT_HEIGHT 720
#define RT_RAY_TMAX 3.402823466e+38f   /* FLT_MAX: primary/bounce rays are unbounded */

typedef struct rt_camera {
    double eye[3], forward[3], right[3], up[3];   /* orthonormal basis */
    double s;                                     /* tan(fov/2) */
    uint32_t width, height;
} rt_camera;

/* Builds the camera for a width x height image (1..65535 each). False with a
 * message for a degenerate view or bad resolution. */
bool rt_camera_init(rt_camera *cam, const rt_view *view, uint32_t width, uint32_t height,
                    char *err, size_t errlen);

/* The primary ray through the centre of pixel (px, py); px < width, py < height. */
rt_ray rt_camera_primary_ray(const rt_camera *cam, uint32_t px, uint32_t py);

/* Parses "WxH" (e.g. "1280x720") into width/height, 1..65535 each. */
bool rt_parse_resolution(const char *text, uint32_t *width, uint32_t *height,
                         char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
