// image_oiio.cpp — the OpenImageIO shim behind image.h (the only C++ in
// tracer/). Uses OIIO 2.x ImageOutput/ImageInput (create, open, write_image,
// read_image, close); see https://openimageio.readthedocs.io ("ImageOutput").
#include "tracer/io/image.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <unistd.h>
#include <vector>

#include "tracer/io/scene_error.h"
#include "tracer/io/scene_file.h"

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

extern "C" bool rt_image_format_supported(const char *path)
{
    return rt_path_has_suffix(path, ".png") || rt_path_has_suffix(path, ".exr");
}

// Writes nchan float channels to path via a temporary file in the same
// folder ("<dir>/.<name>.tmp<pid>"), renamed into place when complete.
static bool write_image(const char *path, const float *pix, uint32_t w, uint32_t h, int nchan,
                        const std::vector<std::string> &names, const char *description, char *err,
                        size_t errlen)
{
    if (!rt_image_format_supported(path)) {
        rt_scene_errorf(err, errlen, "%s: unsupported image type; allowed .png or .exr", path);
        return false;
    }
    if (w < 1 || h < 1 || w > 65535 || h > 65535) {
        rt_scene_errorf(err, errlen, "%s: image size %ux%u out of range 1..65535", path, w, h);
        return false;
    }
    bool exr = rt_path_has_suffix(path, ".exr");
    // The plugin is chosen from the final name; the data goes to the temp name.
    auto out = ImageOutput::create(path);
    if (!out) {
        rt_scene_errorf(err, errlen, "%s: OpenImageIO cannot write this type: %s", path,
                        OIIO::geterror().c_str());
        return false;
    }
    std::string p(path);
    size_t slash = p.rfind('/');
    std::string dir = slash == std::string::npos ? "" : p.substr(0, slash + 1);
    std::string base = slash == std::string::npos ? p : p.substr(slash + 1);
    std::string tmp = dir + "." + base + ".tmp" + std::to_string((long)getpid());
    ImageSpec spec(int(w), int(h), nchan, exr ? TypeDesc::FLOAT : TypeDesc::UINT8);
    if (!names.empty())
        spec.channelnames = names;
    if (description && *description)
        spec.attribute("ImageDescription", description);
    // A fixed capture date: OIIO's EXR writer stamps the current time
    // otherwise, and equal inputs must give bit-identical files.
    spec.attribute("DateTime", "1970:01:01 00:00:00");
    if (!out->open(tmp, spec)) {
        rt_scene_errorf(err, errlen, "%s: cannot open for writing: %s", tmp.c_str(),
                        out->geterror().c_str());
        return false;
    }
    // OIIO converts float to UINT8 for PNG (clamping to [0,1], rounding).
    bool ok = out->write_image(TypeDesc::FLOAT, pix);
    std::string why = ok ? "" : out->geterror();
    if (!out->close() && ok) {
        ok = false;
        why = out->geterror();
    }
    if (!ok) {
        std::remove(tmp.c_str());
        rt_scene_errorf(err, errlen, "%s: write failed: %s", path, why.c_str());
        return false;
    }
    if (std::rename(tmp.c_str(), path) != 0) {
        std::string e = std::strerror(errno);
        std::remove(tmp.c_str());
        rt_scene_errorf(err, errlen, "%s: cannot rename temporary file into place: %s", path, e.c_str());
        return false;
    }
    return true;
}

extern "C" bool rt_image_write_rgb(const char *path, const float *rgb, uint32_t width,
                                   uint32_t height, char *err, size_t errlen)
{
    return write_image(path, rgb, width, height, 3, {}, nullptr, err, errlen);
}

// matplotlib's viridis sampled at 9 evenly spaced points (the widely quoted
// 8-bit stops #440154 #472c7a #3b518b #2c718e #21908d #27ad81 #5cc863 #aadc32
// #fde725), interpolated linearly in between.
static const unsigned char viridis_stops[9][3] = {
    {0x44, 0x01, 0x54}, {0x47, 0x2c, 0x7a}, {0x3b, 0x51, 0x8b}, {0x2c, 0x71, 0x8e}, {0x21, 0x90, 0x8d},
    {0x27, 0xad, 0x81}, {0x5c, 0xc8, 0x63}, {0xaa, 0xdc, 0x32}, {0xfd, 0xe7, 0x25}};

extern "C" void rt_colormap_eval(rt_colormap cmap, float v, float lo, float hi, float rgb[3])
{
    if (!std::isfinite(v)) {
        rgb[0] = 1, rgb[1] = 0, rgb[2] = 1;
        return;
    }
    double t = hi > lo ? (double(v) - lo) / (double(hi) - lo) : 0.0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    if (cmap == RT_COLORMAP_GRAY) {
        rgb[0] = rgb[1] = rgb[2] = float(t);
        return;
    }
    double x = t * 8.0;
    int i = int(x);
    if (i > 7)
        i = 7;
    double f = x - i;
    for (int c = 0; c < 3; c++)
        rgb[c] = float(((1 - f) * viridis_stops[i][c] + f * viridis_stops[i + 1][c]) / 255.0);
}

extern "C" void rt_image_value_range(const float *v, size_t n, float *lo, float *hi)
{
    bool any = false;
    float a = 0, b = 0;
    for (size_t i = 0; i < n; i++) {
        if (!std::isfinite(v[i]))
            continue;
        if (!any || v[i] < a)
            a = v[i];
        if (!any || v[i] > b)
            b = v[i];
        any = true;
    }
    *lo = a;
    *hi = b;
}

extern "C" bool rt_image_write_heatmap(const char *path, const float *values, uint32_t width,
                                       uint32_t height, float lo, float hi, rt_colormap cmap,
                                       char *err, size_t errlen)
{
    if (!(std::isfinite(lo) && std::isfinite(hi) && hi >= lo)) {
        rt_scene_errorf(err, errlen, "%s: heatmap range [%g, %g] invalid; need finite lo <= hi", path,
                        double(lo), double(hi));
        return false;
    }
    bool exr = rt_path_has_suffix(path, ".exr");
    int nchan = exr ? 4 : 3;
    std::vector<float> pix(size_t(width) * height * nchan);
    for (size_t i = 0; i < size_t(width) * height; i++) {
        rt_colormap_eval(cmap, values[i], lo, hi, &pix[i * nchan]);
        if (exr)
            pix[i * nchan + 3] = values[i];
    }
    char desc[200];
    std::snprintf(desc, sizeof desc, "rtsim heatmap colormap=%s range=[%.9g, %.9g]",
                  cmap == RT_COLORMAP_GRAY ? "gray" : "viridis", double(lo), double(hi));
    std::vector<std::string> names;
    if (exr)
        names = {"R", "G", "B", "value"};
    return write_image(path, pix.data(), width, height, nchan, names, desc, err, errlen);
}

extern "C" bool rt_image_read_rgb(const char *path, float **rgb, uint32_t *width, uint32_t *height,
                                  char *err, size_t errlen)
{
    *rgb = nullptr;
    auto in = ImageInput::open(path);
    if (!in) {
        rt_scene_errorf(err, errlen, "%s: cannot read image: %s", path, OIIO::geterror().c_str());
        return false;
    }
    const ImageSpec &spec = in->spec();
    int w = spec.width, h = spec.height, nc = spec.nchannels;
    std::vector<float> all(size_t(w) * h * nc);
    if (!in->read_image(0, 0, 0, nc, TypeDesc::FLOAT, all.data())) {
        rt_scene_errorf(err, errlen, "%s: cannot read pixels: %s", path, in->geterror().c_str());
        in->close();
        return false;
    }
    in->close();
    float *out = static_cast<float *>(std::malloc(size_t(w) * h * 3 * sizeof(float)));
    if (!out) {
        rt_scene_errorf(err, errlen, "%s: out of memory", path);
        return false;
    }
    for (size_t i = 0; i < size_t(w) * h; i++)
        for (int c = 0; c < 3; c++)
            out[i * 3 + c] = all[i * nc + (c < nc ? c : 0)];
    *rgb = out;
    *width = uint32_t(w);
    *height = uint32_t(h);
    return true;
}

extern "C" bool rt_image_read_channel(const char *path, const char *channel, float **values,
                                      uint32_t *width, uint32_t *height, char *err, size_t errlen)
{
    *values = nullptr;
    auto in = ImageInput::open(path);
    if (!in) {
        rt_scene_errorf(err, errlen, "%s: cannot read image: %s", path, OIIO::geterror().c_str());
        return false;
    }
    const ImageSpec &spec = in->spec();
    int c = spec.channelindex(channel);
    if (c < 0) {
        std::string names;
        for (const auto &n : spec.channelnames)
            names += (names.empty() ? "" : ", ") + n;
        rt_scene_errorf(err, errlen, "%s: no channel '%s'; channels: %s", path, channel, names.c_str());
        in->close();
        return false;
    }
    size_t n = size_t(spec.width) * spec.height;
    float *out = static_cast<float *>(std::malloc((n ? n : 1) * sizeof(float)));
    if (!out) {
        rt_scene_errorf(err, errlen, "%s: out of memory", path);
        in->close();
        return false;
    }
    if (!in->read_image(0, 0, c, c + 1, TypeDesc::FLOAT, out)) {
        rt_scene_errorf(err, errlen, "%s: cannot read channel %s: %s", path, channel, in->geterror().c_str());
        std::free(out);
        in->close();
        return false;
    }
    in->close();
    *values = out;
    *width = uint32_t(spec.width);
    *height = uint32_t(spec.height);
    return true;
}

extern "C" bool rt_image_read_description(const char *path, char *desc, size_t desclen, char *err,
                                          size_t errlen)
{
    auto in = ImageInput::open(path);
    if (!in) {
        rt_scene_errorf(err, errlen, "%s: cannot read image: %s", path, OIIO::geterror().c_str());
        return false;
    }
    std::string d = in->spec().get_string_attribute("ImageDescription");
    in->close();
    if (desclen)
        std::snprintf(desc, desclen, "%s", d.c_str());
    return true;
}
