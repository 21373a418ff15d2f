/* image.h — writing frames and heatmaps through OpenImageIO (C shim over
 * image_oiio.cpp).
 *
 * Format by file extension: .png (8-bit, values clamped to [0,1] and
 * quantized by OIIO) or .exr (32-bit float, exact). Pixel (0,0) is the top
 * left; buffers are row-major, width*height pixels. Files are written to a
 * temporary name in the same folder and renamed when complete, so a failed
 * write never leaves a partial file under the final name. Errors return false
 * with "FILE: reason". */
#ifndef RTSIM_TRACER_IMAGE_H
#define RTSIM_TRACER_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rt_colormap {
    RT_COLORMAP_VIRIDIS = 0,   /* matplotlib's viridis (van der Walt & Smith, CC0) */
    RT_COLORMAP_GRAY = 1
} rt_colormap;

/* True for paths ending .png or .exr (case-insensitive). */
bool rt_image_format_supported(const char *path);

/* Writes a float RGB buffer (3*w*h floats). */
bool rt_image_write_rgb(const char *path, const float *rgb, uint32_t width, uint32_t height,
                        char *err, size_t errlen);

/* Maps value v to a colour: t = (v - lo)/(hi - lo) clamped to [0,1]
 * (non-finite v -> magenta, hi <= lo -> t = 0). rgb[3] in [0,1]. */
void rt_colormap_eval(rt_colormap cmap, float v, float lo, float hi, float rgb[3]);

/* Smallest and largest finite value of v[0..n) (both 0 when there is none):
 * the usual [lo, hi] of a heatmap. */
void rt_image_value_range(const float *v, size_t n, float *lo, float *hi);

/* Writes a heatmap of one scalar per pixel mapped through cmap over [lo, hi].
 * The range and map are stored in the image's ImageDescription metadata; an
 * .exr also gets a fourth channel "value" holding the raw scalars. */
bool rt_image_write_heatmap(const char *path, const float *values, uint32_t width,
                            uint32_t height, float lo, float hi, rt_colormap cmap,
                            char *err, size_t errlen);

/* Reads an image's first three channels as float RGB (malloc'ed, caller
 * frees); grey images are replicated. For tests and tools. */
bool rt_image_read_rgb(const char *path, float **rgb, uint32_t *width, uint32_t *height,
                       char *err, size_t errlen);

/* Reads the channel called `channel` (e.g. "value" of an .exr heatmap, or
 * "R") as one float per pixel (malloc'ed, caller frees); false with a
 * message listing the channels when there is none of that name. */
bool rt_image_read_channel(const char *path, const char *channel, float **values, uint32_t *width,
                           uint32_t *height, char *err, size_t errlen);

/* Reads the ImageDescription metadata into desc (empty when absent). */
bool rt_image_read_description(const char *path, char *desc, size_t desclen,
                               char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
