// encode.cpp — the OpenImageIO half of src/image, built as the plugin libtocher_image.so:
// encodes tiles to PNG, OpenEXR and TIFF entirely in memory, and decodes them back for tests.

// plugin.c opens this file with dlopen on the first image encode, so processes that never
// write an image never pay for OpenImageIO. Only the extern "C" functions at the end are
// the interface; nothing may throw across them. codec.c validates every input first
// against the format table (dimensions, channel counts, alpha, the format), so the checks
// here only guard memory safety.
//
// Conversions (all exactly reproducible, so the tests can compare bit for bit):
//   PNG / PNG16  x = v * 2^exposure; x = sRGB(x) unless im->linear; clamp to [0,1] (NaN -> 0);
//                q = floor(x * M + 0.5), M = 255 or 65535. We quantize ourselves and hand
//                OpenImageIO uint8/uint16 samples, which it writes untouched.
//                Alpha: the same clamp and rounding of a, with no exposure or transfer.
//   EXR          the floats as given (half: OpenImageIO's float->half, round to nearest;
//                beyond +-65504 becomes +-inf). Alpha "A", stored as given.
//   TIFF         the floats as given, 32-bit, alpha as an unassociated extra sample. OpenImageIO
//                writes 3+ samples as RGB (+ extra samples), so 2 channels + alpha cannot be
//                tagged: codec.c refuses that case rather than write alpha as "blue" (its row's alpha rule).
//   (RAW never reaches this file: codec.c writes it without loading OpenImageIO.)
//
// Compression, measured on a synthetic 1024x1024 RGB float tile (smooth falloff, a shadow
// edge, an empty corner; 12.6 MB of samples; 2 busy cores, so times vary by up to 2x):
//   EXR float: none 12.6 MB 21 ms, rle 12.1 MB 45 ms, zip 10.4 MB 183 ms, piz 8.3 MB 164 ms
//              -> piz: the smallest lossless choice at zip's cost (none if latency on a fast
//              network matters more than size: full-precision floats barely compress).
//   EXR half:  none 6.3 MB 20 ms, piz 1.22 MB 24 ms, zip 0.48 MB 32 ms -> zip
//   TIFF float: lzw 6.9 MB 109 ms, zip (deflate + float predictor) 4.6 MB 240 ms -> zip
//   PNG: OpenImageIO's default zlib level 6 (8-bit 0.17 MB 90 ms; level 1: 0.31 MB 45 ms).
#include "image/image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#define TC_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// An encode or decode failure: the message that ends up in the caller's err.
struct Failure {
    std::string msg;
};

void set_err(char *err, size_t errlen, const std::string &msg) {
    if (err && errlen) std::snprintf(err, errlen, "%s", msg.c_str());
}

// OpenImageIO's pending error for `who` (an ImageInput/ImageOutput), or the global
// one, or `fallback` when neither says anything.
template <class T> std::string oiio_error(const T *who, const char *fallback) {
    std::string e = who ? who->geterror() : std::string();
    if (e.empty()) e = OIIO::geterror();
    return e.empty() ? std::string(fallback) : e;
}

size_t npixels(const tc_img *im) { return (size_t)im->width * (size_t)im->height; }

// ---- PNG: our own exposure, transfer and quantization ----------------------------

double srgb_encode(double x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055; }

// Clamps to [0,1] (NaN counts as 0) and rounds to the nearest of 0..maxval.
double quantize(double x, double maxval) {
    if (!(x > 0.0)) x = 0.0;
    if (x > 1.0) x = 1.0;
    return std::floor(x * maxval + 0.5);
}

// Interleaves the converted samples (plus alpha) as T: [h][w][channels (+1)].
template <class T> std::vector<T> png_samples(const tc_img *im, double maxval) {
    const int nc = im->channels, out_nc = nc + (im->alpha ? 1 : 0);
    const double scale = std::exp2(im->exposure);
    const size_t n = npixels(im);
    std::vector<T> out(n * (size_t)out_nc);
    for (size_t p = 0; p < n; p++) {
        for (int c = 0; c < nc; c++) {
            double x = (double)im->pixels[p * (size_t)nc + (size_t)c] * scale;
            if (!im->linear) x = srgb_encode(x);
            out[p * (size_t)out_nc + (size_t)c] = (T)quantize(x, maxval);
        }
        if (im->alpha) out[p * (size_t)out_nc + (size_t)nc] = (T)quantize(im->alpha[p], maxval);
    }
    return out;
}

// ---- float formats: the samples as given, alpha appended when there is one ----------

// Returns im->pixels itself when there is no alpha; else fills `buf` with
// [h][w][channels + 1] and returns it.
const float *float_samples(const tc_img *im, std::vector<float> &buf) {
    if (!im->alpha) return im->pixels;
    const size_t n = npixels(im), nc = (size_t)im->channels;
    buf.resize(n * (nc + 1));
    for (size_t p = 0; p < n; p++) {
        std::memcpy(&buf[p * (nc + 1)], &im->pixels[p * nc], nc * sizeof(float));
        buf[p * (nc + 1) + nc] = im->alpha[p];
    }
    return buf.data();
}

// Y; R,G,B; else ch0..chN, zero-padded past 10 channels so that OpenEXR's
// alphabetical channel order on disk is also the numeric order. Then A.
std::vector<std::string> channel_names(const tc_img *im) {
    std::vector<std::string> names;
    if (im->channels == 1) {
        names = {"Y"};
    } else if (im->channels == 3) {
        names = {"R", "G", "B"};
    } else {
        const int width = im->channels > 10 ? 2 : 1;
        for (int c = 0; c < im->channels; c++) {
            char b[16];
            std::snprintf(b, sizeof b, "ch%0*d", width, c);
            names.push_back(b);
        }
    }
    if (im->alpha) names.push_back("A");
    return names;
}

// The spec shared by every format: size, sample type, channel names and alpha.
// Alpha is coverage kept apart from the colour (unassociated): OpenImageIO must not
// premultiply or divide by it.
ImageSpec base_spec(const tc_img *im, TypeDesc stored) {
    const int nc = im->channels + (im->alpha ? 1 : 0);
    ImageSpec spec(im->width, im->height, nc, stored);
    spec.channelnames = channel_names(im);
    spec.alpha_channel = im->alpha ? im->channels : -1;
    if (im->alpha) spec.attribute("oiio:UnassociatedAlpha", 1);
    // Else the EXR and TIFF writers stamp the current time: the same tile must give the
    // same bytes (caches, ETags, tests). An empty DateTime writes no date at all.
    spec.attribute("DateTime", "");
    return spec;
}

// ---- writing through OpenImageIO into memory ------------------------------------

// Writes one image of `data` (samples of type `given`) with `spec` as format `ext`
// into `bytes`, through an in-memory proxy (no temporary file).
void write_memory(const char *ext, const ImageSpec &spec, TypeDesc given, const void *data,
                  std::vector<unsigned char> &bytes) {
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = ImageOutput::create(ext, &proxy);
    if (!out)
        throw Failure{std::string("no OpenImageIO writer for ") + ext + ": " + oiio_error<ImageOutput>(nullptr, "?")};
    if (!out->open(std::string("tile.") + ext, spec))
        throw Failure{std::string(ext) + ": " + oiio_error(out.get(), "cannot open the in-memory output")};
    if (!out->write_image(given, data)) {
        std::string e = oiio_error(out.get(), "write failed");
        out->close();
        throw Failure{std::string(ext) + ": " + e};
    }
    if (!out->close()) throw Failure{std::string(ext) + ": " + oiio_error(out.get(), "close failed")};
}

void encode_png(const tc_img *im, bool sixteen, std::vector<unsigned char> &bytes) {
    ImageSpec spec = base_spec(im, sixteen ? TypeDesc::UINT16 : TypeDesc::UINT8);
    // Tags the file (sRGB chunk, or gAMA 1.0) with the transfer we applied.
    spec.attribute("oiio:ColorSpace", im->linear ? "Linear" : "sRGB");
    if (sixteen) {
        std::vector<uint16_t> s = png_samples<uint16_t>(im, 65535.0);
        write_memory("png", spec, TypeDesc::UINT16, s.data(), bytes);
    } else {
        std::vector<uint8_t> s = png_samples<uint8_t>(im, 255.0);
        write_memory("png", spec, TypeDesc::UINT8, s.data(), bytes);
    }
}

void encode_exr(const tc_img *im, bool half, std::vector<unsigned char> &bytes) {
    ImageSpec spec = base_spec(im, half ? TypeDesc::HALF : TypeDesc::FLOAT);
    spec.attribute("compression", half ? "zip" : "piz"); // see the measurements above
    std::vector<float> buf;
    write_memory("exr", spec, TypeDesc::FLOAT, float_samples(im, buf), bytes);
}

void encode_tiff(const tc_img *im, std::vector<unsigned char> &bytes) {
    ImageSpec spec = base_spec(im, TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    std::vector<float> buf;
    write_memory("tif", spec, TypeDesc::FLOAT, float_samples(im, buf), bytes);
}

// Every format of the table (format.h) has a case, and there is no default: a format
// added to the enum without one here fails to compile (-Wswitch, -Werror).
void encode_any(const tc_img *im, tc_img_format f, std::vector<unsigned char> &bytes) {
    switch (f) {
    case TC_IMG_PNG: return encode_png(im, false, bytes);
    case TC_IMG_PNG16: return encode_png(im, true, bytes);
    case TC_IMG_EXR: return encode_exr(im, false, bytes);
    case TC_IMG_EXR_HALF: return encode_exr(im, true, bytes);
    case TC_IMG_TIFF: return encode_tiff(im, bytes);
    case TC_IMG_RAW:      // written in C (codec.c), never handed here
    case TC_IMG_NFORMATS: break;
    }
    throw Failure{"the image plugin does not encode this format"};
}

// A malloc()ed copy (never empty), so that C frees it with free().
unsigned char *malloc_copy(const std::vector<unsigned char> &v) {
    unsigned char *p = (unsigned char *)std::malloc(v.empty() ? 1 : v.size());
    if (!p) throw Failure{"out of memory"};
    if (!v.empty()) std::memcpy(p, v.data(), v.size());
    return p;
}

// ---- decoding (tests) -------------------------------------------------------------

// The reader for the bytes' signature; the format is not guessed from a name.
const char *sniff(const unsigned char *d, size_t n) {
    if (n >= 8 && std::memcmp(d, "\x89PNG\r\n\x1a\n", 8) == 0) return "png";
    if (n >= 4 && std::memcmp(d, "\x76\x2f\x31\x01", 4) == 0) return "exr";
    if (n >= 4 && (std::memcmp(d, "II*\0", 4) == 0 || std::memcmp(d, "MM\0*", 4) == 0)) return "tif";
    throw Failure{"not a PNG, OpenEXR or TIFF file"};
}

template <size_t N> void copy_field(char (&dst)[N], const std::string &s) {
    std::snprintf(dst, N, "%s", s.c_str());
}

std::string joined_names(const ImageSpec &spec) {
    std::string s;
    for (size_t i = 0; i < spec.channelnames.size(); i++) s += (i ? "," : "") + spec.channelnames[i];
    return s;
}

void describe(const ImageSpec &spec, const char *format, tc_img_decoded *out) {
    out->width = spec.width;
    out->height = spec.height;
    out->channels = spec.nchannels;
    out->alpha_channel = spec.alpha_channel;
    copy_field(out->format, format);
    copy_field(out->type, spec.format.c_str());
    copy_field(out->names, joined_names(spec));
    copy_field(out->colorspace, spec.get_string_attribute("oiio:ColorSpace"));
    copy_field(out->compression, spec.get_string_attribute("compression"));
}

void decode_any(const unsigned char *data, size_t len, tc_img_decoded *out) {
    const char *ext = sniff(data, len);
    OIIO::Filesystem::IOMemReader proxy(data, len);
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1); // give alpha back as written
    // open() with a config takes the proxy from the config (and drops one set before).
    OIIO::Filesystem::IOProxy *proxy_ptr = &proxy;
    config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy_ptr);
    auto in = ImageInput::create(ext, false, &config, &proxy);
    if (!in)
        throw Failure{std::string("no OpenImageIO reader for ") + ext + ": " + oiio_error<ImageInput>(nullptr, "?")};
    ImageSpec spec;
    if (!in->open(std::string("tile.") + ext, spec, config))
        throw Failure{std::string(ext) + ": " + oiio_error(in.get(), "cannot open")};
    std::vector<float> px((size_t)spec.width * (size_t)spec.height * (size_t)spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, px.data()))
        throw Failure{std::string(ext) + ": " + oiio_error(in.get(), "read failed")};
    describe(spec, in->format_name(), out);
    out->pixels = (float *)std::malloc(px.size() * sizeof(float) + 1);
    if (!out->pixels) throw Failure{"out of memory"};
    std::memcpy(out->pixels, px.data(), px.size() * sizeof(float));
}

} // namespace

// ---- the C interface resolved by plugin.c -------------------------------------------

TC_EXPORT int tc_img_plugin_abi(void) { return TC_IMG_PLUGIN_ABI; }

TC_EXPORT int tc_img_encode_impl(const tc_img *im, tc_img_format f, unsigned char **out, size_t *len, char *err,
                                 size_t errlen) {
    try {
        if (!im || !im->pixels || !out || !len || im->width < 1 || im->height < 1 || im->channels < 1)
            throw Failure{"invalid image"};
        std::vector<unsigned char> bytes;
        encode_any(im, f, bytes);
        *out = malloc_copy(bytes);
        *len = bytes.size();
        return 0;
    } catch (const Failure &e) {
        set_err(err, errlen, e.msg);
    } catch (const std::exception &e) {
        set_err(err, errlen, std::string("image encoding failed: ") + e.what());
    } catch (...) {
        set_err(err, errlen, "image encoding failed");
    }
    return -1;
}

TC_EXPORT int tc_img_decode_impl(const unsigned char *data, size_t len, tc_img_decoded *out, char *err,
                                 size_t errlen) {
    try {
        if (!data || !out) throw Failure{"invalid arguments"};
        *out = tc_img_decoded{};
        decode_any(data, len, out);
        return 0;
    } catch (const Failure &e) {
        set_err(err, errlen, e.msg);
    } catch (const std::exception &e) {
        set_err(err, errlen, std::string("image decoding failed: ") + e.what());
    } catch (...) {
        set_err(err, errlen, "image decoding failed");
    }
    return -1;
}
