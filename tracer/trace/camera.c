/* camera.c — see camera.h. */
#include "tracer/trace/camera.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "tracer/util/det_math.h"
#include "tracer/io/scene_error.h"

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

bool rt_camera_init(rt_camera *cam, const rt_view *view, uint32_t width, uint32_t height,
                    char *err, size_t errlen)
{
    if (width < 1 || width > 65535 || height < 1 || height > 65535) {
        rt_scene_errorf(err, errlen, "resolution %ux%u out of range; allowed 1..65535 each",
                        width, height);
        return false;
    }
    if (!rt_view_validate(view, "camera", 0, err, errlen))
        return false;
    cam->eye[0] = view->eye.x, cam->eye[1] = view->eye.y, cam->eye[2] = view->eye.z;
    cam->forward[0] = (double)view->at.x - view->eye.x;
    cam->forward[1] = (double)view->at.y - view->eye.y;
    cam->forward[2] = (double)view->at.z - view->eye.z;
    normalize3(cam->forward);
    double up[3] = {view->up.x, view->up.y, view->up.z};
    cross3(cam->forward, up, cam->right);
    normalize3(cam->right);
    cross3(cam->right, cam->forward, cam->up);
    cam->s = rt_det_tan(view->fov_deg * (M_PI / 360.0));
    cam->width = width;
    cam->height = height;
    return true;
}

rt_ray rt_camera_primary_ray(const rt_camera *cam, uint32_t px, uint32_t py)
{
    double w = cam->width, h = cam->height;
    double u = (2.0 * (px + 0.5) / w - 1.0) * cam->s * w / h;
    double v = (1.0 - 2.0 * (py + 0.5) / h) * cam->s;
    double d[3];
    for (int i = 0; i < 3; i++)
        d[i] = cam->forward[i] + u * cam->right[i] + v * cam->up[i];
    normalize3(d);
    rt_ray r;
    r.org = (rt_vec3){(float)cam->eye[0], (float)cam->eye[1], (float)cam->eye[2]};
    r.dir = (rt_vec3){(float)d[0], (float)d[1], (float)d[2]};
    r.tmin = 0.0f;
    r.tmax = RT_RAY_TMAX;
    r.pixel = py * cam->width + px;
    r.bounce = 0;
    r.occlusion = 0;
    return r;
}

bool rt_parse_resolution(const char *text, uint32_t *width, uint32_t *height, char *err,
                         size_t errlen)
{
    unsigned long w = 0, h = 0;
    char *end;
    const char *p = text;
    if (*p >= '0' && *p <= '9') {
        w = strtoul(p, &end, 10);
        if (*end == 'x' || *end == 'X') {
            p = end + 1;
            if (*p >= '0' && *p <= '9') {
                h = strtoul(p, &end, 10);
                if (*end == 0 && w >= 1 && w <= 65535 && h >= 1 && h <= 65535) {
                    *width = (uint32_t)w;
                    *height = (uint32_t)h;
                    return true;
                }
            }
        }
    }
    rt_scene_errorf(err, errlen, "bad resolution '%s'; expected WxH with 1..65535 each, e.g. 1280x720",
                    text);
    return false;
}
