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
//   PNG: OpenImageIO's default zlib level 6 (8-bit 0.17 MB 90 ms; level 1: 0.31 MB 45 ms), rows
//        filtered by "sub" alone rather than libpng's choice per row among all five: six 256²
//        grey tiles (grid64, penumbra and box, whole and a quarter) 51.9 KB in 38.6 ms -> 47.9 KB
//        in 30.3 ms (paeth alone 51.1 KB, 34.3 ms; level 4 with sub 65.5 KB, 13.0 ms: a tile is
//        encoded once and sent many times, so the level stays).
#include "image/image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <exception>
#include <memory>
#include <mutex>
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

// q(v) = quantize(transfer(v * scale), maxval) for every float v, without a pow per sample.
// q is non-decreasing in v (the product, the sRGB curve, the clamp and the rounding all are),
// so q(v) is the number of thresholds t[k] <= v, t[k] the least float with q >= k (k = 1 ..
// maxval), each found once by bisection on q itself: the same answers as q, bit for bit (the
// tests compare every sample with the formula, and sampled floats and every threshold's
// neighbours with q). A table indexed by the float's top bits gives the count at the start of
// each bucket; a sample then steps over the (at most few) thresholds in its bucket. The sRGB
// transfer per sample was a quarter of a daemon's CPU serving 256² PNG tiles (pow, floor and
// this loop); a table costs ~1K evaluations of q for 8 bits, ~0.2M (~10 ms) for 16, and the
// last few made are kept (quantizer()).
class Quantizer {
  public:
    Quantizer(double scale, bool linear, double maxval) : m_scale(scale), m_linear(linear), m_maxval(maxval) {
        const int levels = (int)maxval;
        m_top = level(INF_BITS); // maxval, unless scale is 0 (then inf * 0 is NaN: 0)
        m_t.resize((size_t)levels + 2);
        m_t[0] = 0;
        int finite = 0; // the last level some finite float reaches
        for (int k = 1; k <= levels; k++) {
            m_t[(size_t)k] = least_reaching(k, m_t[(size_t)k - 1]);
            if (m_t[(size_t)k] < INF_BITS) finite = k;
        }
        m_t[(size_t)levels + 1] = UINT32_MAX; // a sentinel no sample passes
        m_shift = levels > 255 ? 9 : 13;      // 2^14 or 2^10 buckets an octave
        m_first = m_t[1] >> m_shift;
        uint32_t last = finite ? m_t[(size_t)finite] >> m_shift : m_first;
        m_start.resize((size_t)(last - m_first) + 1);
        int k = 0; // thresholds at or below the bucket's first float
        for (uint32_t b = m_first; b <= last; b++) {
            while (k < levels && m_t[(size_t)k + 1] <= (b << m_shift)) k++;
            m_start[b - m_first] = (uint16_t)k;
        }
    }
    bool fits(double scale, bool linear, double maxval) const {
        return scale == m_scale && linear == m_linear && maxval == m_maxval;
    }
    // The level of v: quantize(transfer(v * scale), maxval).
    uint32_t operator()(float v) const {
        if (!(v > 0.0f)) return 0; // zero, negative, NaN
        uint32_t u;
        std::memcpy(&u, &v, sizeof u);
        if (u < m_t[1]) return 0;
        uint32_t b = (u >> m_shift) - m_first;
        uint32_t k = b < m_start.size() ? m_start[b] : m_start.back();
        while (u >= m_t[(size_t)k + 1]) k++;
        return k;
    }

  private:
    static constexpr uint32_t INF_BITS = 0x7f800000u; // positive floats order as their bits
    static constexpr uint32_t UNREACHED = INF_BITS + 1; // past +inf: a level no float reaches
    double level(uint32_t u) const {
        float v;
        std::memcpy(&v, &u, sizeof v);
        double x = (double)v * m_scale;
        if (!m_linear) x = srgb_encode(x);
        return quantize(x, m_maxval);
    }
    // Where level k begins, about: the transfer inverted at (k - 1/2) / maxval.
    uint32_t estimate(int k) const {
        double y = (k - 0.5) / m_maxval;
        double x = m_linear ? y : y <= 12.92 * 0.0031308 ? y / 12.92 : std::pow((y + 0.055) / 1.055, 2.4);
        double v = x / m_scale;
        if (!(v > 0) || !(v < FLT_MAX)) return 0; // no guess: search from the last threshold
        float f = (float)v;
        uint32_t u;
        std::memcpy(&u, &f, sizeof u);
        return u;
    }
    // The bits of the least float from lo (the previous threshold) up to +inf whose level is
    // >= k: from the estimate a float at a time while that finds it within a few (two or three
    // levels computed, the usual case), else by bisection between lo and +inf.
    uint32_t least_reaching(int k, uint32_t lo) const {
        if (k > m_top) return UNREACHED;
        if (level(lo) >= k) return lo;
        uint32_t e = estimate(k);
        if (e > lo + 4 && e < INF_BITS - 4) {
            bool above = level(e) >= k; // walk towards the boundary, at most 4 floats
            for (int step = 0; step < 4; step++) {
                uint32_t next = above ? e - 1 : e + 1;
                bool next_above = level(next) >= k;
                if (above != next_above) return above ? e : next;
                e = next;
            }
        }
        uint32_t a = lo, b = INF_BITS; // level(a) < k <= level(b)
        while (b - a > 1) {
            uint32_t m = a + (b - a) / 2;
            if (level(m) >= k) b = m;
            else a = m;
        }
        return b;
    }
    double m_scale;
    bool m_linear;
    double m_maxval;
    double m_top = 0;              // the level of +inf
    std::vector<uint32_t> m_t;     // [0] 0, [k] threshold k's bits, [maxval + 1] a sentinel
    std::vector<uint16_t> m_start; // thresholds <= the first float of each bucket from m_first
    uint32_t m_first = 0;
    int m_shift = 13;
};

// The quantizer for this band's conversion: the last few made, shared by every thread (a
// daemon answers each connection on a thread of its own, and tile after tile of a viewer
// comes with the same exposure). A quantizer never changes once made; one is made under the
// lock, so a second thread that wants it waits for it rather than making it again.
std::shared_ptr<const Quantizer> quantizer(double scale, bool linear, double maxval) {
    static std::mutex lock;
    static std::shared_ptr<const Quantizer> kept[4]; // most recently used first
    std::lock_guard<std::mutex> hold(lock);
    int i = 0;
    while (i < 4 && !(kept[i] && kept[i]->fits(scale, linear, maxval))) i++;
    std::shared_ptr<const Quantizer> q = i < 4 ? kept[i] : std::make_shared<const Quantizer>(scale, linear, maxval);
    for (int j = i < 4 ? i : 3; j > 0; j--) kept[j] = kept[j - 1];
    kept[0] = q;
    return q;
}

// The level of an alpha: clamped and rounded, no exposure or transfer (0 and 1 at once).
double alpha_level(float a, double maxval) { return a == 0.0f ? 0.0 : a == 1.0f ? maxval : quantize(a, maxval); }

// Interleaves the converted samples of a band (plus alpha) as T into out:
// [rows][w][channels (+1)].
template <class T> void png_samples(const tc_img *band, double maxval, std::vector<T> &out) {
    const int nc = band->channels, out_nc = nc + (band->alpha ? 1 : 0);
    std::shared_ptr<const Quantizer> kept = quantizer(std::exp2(band->exposure), band->linear != 0, maxval);
    const Quantizer &q = *kept;
    const size_t n = npixels(band);
    out.resize(n * (size_t)out_nc);
    for (size_t p = 0; p < n; p++) {
        for (int c = 0; c < nc; c++) out[p * (size_t)out_nc + (size_t)c] = (T)q(band->pixels[p * (size_t)nc + (size_t)c]);
        if (band->alpha) out[p * (size_t)out_nc + (size_t)nc] = (T)alpha_level(band->alpha[p], maxval);
    }
}

// ---- float formats: the samples as given, alpha appended when there is one ----------

// Returns band->pixels itself when there is no alpha; else fills `buf` with
// [rows][w][channels + 1] and returns it.
const float *float_samples(const tc_img *band, std::vector<float> &buf) {
    if (!band->alpha) return band->pixels;
    const size_t n = npixels(band), nc = (size_t)band->channels;
    buf.resize(n * (nc + 1));
    for (size_t p = 0; p < n; p++) {
        std::memcpy(&buf[p * (nc + 1)], &band->pixels[p * nc], nc * sizeof(float));
        buf[p * (nc + 1) + nc] = band->alpha[p];
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

// Each format's spec: stored sample type, compression and colour tags (the
// compression choices are measured at the top of this file).
ImageSpec format_spec(const tc_img *im, tc_img_format f) {
    switch (f) {
    case TC_IMG_PNG:
    case TC_IMG_PNG16: {
        ImageSpec spec = base_spec(im, f == TC_IMG_PNG16 ? TypeDesc::UINT16 : TypeDesc::UINT8);
        // Tags the file (sRGB chunk, or gAMA 1.0) with the transfer we applied.
        spec.attribute("oiio:ColorSpace", im->linear ? "Linear" : "sRGB");
        spec.attribute("png:filter", 16); // PNG_FILTER_SUB (measured at the top of this file)
        return spec;
    }
    case TC_IMG_EXR:
    case TC_IMG_EXR_HALF: {
        ImageSpec spec = base_spec(im, f == TC_IMG_EXR_HALF ? TypeDesc::HALF : TypeDesc::FLOAT);
        spec.attribute("compression", f == TC_IMG_EXR_HALF ? "zip" : "piz");
        return spec;
    }
    case TC_IMG_TIFF: {
        ImageSpec spec = base_spec(im, TypeDesc::FLOAT);
        spec.attribute("compression", "zip");
        return spec;
    }
    case TC_IMG_RAW:      // written in C (codec.c), never handed here
    case TC_IMG_NFORMATS: break;
    }
    // Every format of the table (format.h) has a case above, and there is no default: a
    // format added to the enum without one fails to compile (-Wswitch, -Werror).
    throw Failure{"the image plugin does not encode this format"};
}

const char *extension(tc_img_format f) {
    return f == TC_IMG_TIFF ? "tif" : f == TC_IMG_EXR || f == TC_IMG_EXR_HALF ? "exr" : "png";
}

// ---- writing through OpenImageIO into memory ------------------------------------

// An output proxy that writes into one malloc()ed buffer grown with realloc, so
// the finished file is handed to the caller as it is (no copy: the answer is
// held once). Large blocks grow in place or by remapping (glibc's mremap), and
// capacity not yet written is never touched, so it costs no resident memory.
// Invariant: len <= cap, and cap > len once anything is written (room for a NUL).
class MallocOutput : public OIIO::Filesystem::IOProxy {
  public:
    MallocOutput() : IOProxy("", Write) {}
    ~MallocOutput() override { std::free(m_data); }
    const char *proxytype() const override { return "tocher-malloc"; }
    size_t write(const void *buf, size_t size) override {
        size_t n = pwrite(buf, size, m_pos);
        m_pos += (int64_t)n;
        return n;
    }
    size_t pwrite(const void *buf, size_t size, int64_t offset) override {
        if (offset < 0 || !reserve((size_t)offset + size + 1)) return 0;
        if ((size_t)offset > m_len) std::memset(m_data + m_len, 0, (size_t)offset - m_len);
        std::memcpy(m_data + offset, buf, size);
        if ((size_t)offset + size > m_len) m_len = (size_t)offset + size;
        return size;
    }
    size_t pread(void *buf, size_t size, int64_t offset) override {
        if (offset < 0 || (size_t)offset >= m_len) return 0;
        size_t n = std::min(size, m_len - (size_t)offset);
        std::memcpy(buf, m_data + offset, n);
        return n;
    }
    size_t read(void *buf, size_t size) override {
        size_t n = pread(buf, size, m_pos);
        m_pos += (int64_t)n;
        return n;
    }
    size_t size() const override { return m_len; }
    // Hands the bytes over: the caller frees them; the proxy is empty after.
    unsigned char *release(size_t *len, size_t *cap) {
        if (!reserve(m_len + 1)) throw Failure{"out of memory"};
        unsigned char *p = m_data;
        *len = m_len, *cap = m_cap;
        m_data = nullptr, m_len = m_cap = 0;
        return p;
    }

  private:
    bool reserve(size_t need) {
        if (need <= m_cap) return true;
        size_t cap = std::max(need, m_cap < 4096 ? (size_t)4096 : m_cap + m_cap / 2);
        unsigned char *p = (unsigned char *)std::realloc(m_data, cap);
        if (!p) return false;
        m_data = p, m_cap = cap;
        return true;
    }
    unsigned char *m_data = nullptr;
    size_t m_len = 0, m_cap = 0;
};

// One image being written: the proxy that holds its bytes, the OpenImageIO
// writer, and the conversion scratch for one band (the only per-band memory).
struct Stream {
    tc_img header;
    tc_img_format f;
    int y = 0; // the next row
    MallocOutput proxy;
    std::unique_ptr<ImageOutput> out;
    std::vector<uint8_t> s8;
    std::vector<uint16_t> s16;
    std::vector<float> sf;
};

void stream_open(Stream &s) {
    const char *ext = extension(s.f);
    ImageSpec spec = format_spec(&s.header, s.f);
    s.out = ImageOutput::create(ext, &s.proxy);
    if (!s.out)
        throw Failure{std::string("no OpenImageIO writer for ") + ext + ": " + oiio_error<ImageOutput>(nullptr, "?")};
    if (!s.out->open(std::string("tile.") + ext, spec))
        throw Failure{std::string(ext) + ": " + oiio_error(s.out.get(), "cannot open the in-memory output")};
}

void stream_rows(Stream &s, const tc_img *band) {
    const void *data;
    TypeDesc given;
    if (s.f == TC_IMG_PNG) png_samples<uint8_t>(band, 255.0, s.s8), data = s.s8.data(), given = TypeDesc::UINT8;
    else if (s.f == TC_IMG_PNG16)
        png_samples<uint16_t>(band, 65535.0, s.s16), data = s.s16.data(), given = TypeDesc::UINT16;
    else data = float_samples(band, s.sf), given = TypeDesc::FLOAT;
    if (!s.out->write_scanlines(s.y, s.y + band->height, 0, given, data))
        throw Failure{std::string(extension(s.f)) + ": " + oiio_error(s.out.get(), "write failed")};
    s.y += band->height;
}

unsigned char *stream_finish(Stream &s, size_t *len, size_t *cap) {
    bool ok = s.out->close();
    std::string e = ok ? "" : oiio_error(s.out.get(), "close failed");
    s.out.reset();
    if (!ok) throw Failure{std::string(extension(s.f)) + ": " + e};
    return s.proxy.release(len, cap);
}

// Runs f, turning any exception into -1 and a message in err.
template <class F> int guarded(const char *what, char *err, size_t errlen, F f) {
    try {
        f();
        return 0;
    } catch (const Failure &e) {
        set_err(err, errlen, e.msg);
    } catch (const std::exception &e) {
        set_err(err, errlen, std::string("image ") + what + " failed: " + e.what());
    } catch (...) {
        set_err(err, errlen, std::string("image ") + what + " failed");
    }
    return -1;
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

TC_EXPORT void *tc_img_stream_open(const tc_img *header, tc_img_format f, char *err, size_t errlen) {
    Stream *s = nullptr;
    int rc = guarded("encoding", err, errlen, [&] {
        if (!header || header->width < 1 || header->height < 1 || header->channels < 1) throw Failure{"invalid image"};
        s = new Stream;
        s->header = *header;
        s->f = f;
        stream_open(*s);
    });
    if (rc == 0) return s;
    delete s;
    return nullptr;
}

TC_EXPORT int tc_img_stream_rows(void *s, const tc_img *band, char *err, size_t errlen) {
    return guarded("encoding", err, errlen, [&] {
        Stream &st = *(Stream *)s;
        if (!band->pixels || band->height < 1 || band->height > st.header.height - st.y) throw Failure{"invalid band"};
        stream_rows(st, band);
    });
}

TC_EXPORT int tc_img_stream_finish(void *s, unsigned char **out, size_t *len, size_t *cap, char *err,
                                   size_t errlen) {
    return guarded("encoding", err, errlen, [&] { *out = stream_finish(*(Stream *)s, len, cap); });
}

TC_EXPORT void tc_img_stream_free(void *s) { delete (Stream *)s; }

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
