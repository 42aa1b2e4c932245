#include "Image.h"

#include "../Error.h"

#ifdef WAVEVCM_HAVE_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace wv {

static std::string extensionOf(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// The temporary name an image is written under, beside `path`; it keeps the
// extension, from which OpenImageIO picks the format (and, for .pfm, float
// rather than 8-bit PNM).
static std::filesystem::path partialPath(const std::string& path)
{
    std::filesystem::path target(path);
    return target.parent_path() /
           ("." + target.stem().string() + ".partial" + std::to_string(::getpid()) + target.extension().string());
}

// Moves the finished temporary file onto `path` (atomic within a directory).
static void commitPartial(const std::filesystem::path& tmp, const std::string& path)
{
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw Error(path + ": cannot write image: " + ec.message());
    }
}

void checkWritable(const std::string& path)
{
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": cannot write: is a directory");
    if (std::filesystem::exists(path, ec) && ::access(path.c_str(), W_OK) != 0)
        throw Error(path + ": cannot write: the file is read-only");
    std::filesystem::path probe = partialPath(path);
    {
        std::ofstream out(probe, std::ios::binary);
        if (!out) {
            std::filesystem::path dir = std::filesystem::path(path).parent_path();
            std::string why = dir.empty() || std::filesystem::is_directory(dir, ec) ? "permission denied or read-only"
                                                                                    : "no such directory";
            throw Error(path + ": cannot write: " + why);
        }
    }
    std::filesystem::remove(probe, ec);
}

// Portable float map: "PF", size, a negative scale for little-endian, then
// float RGB rows from the bottom up. Written here because Debian's
// OpenImageIO 2.4 reads PFM but has no PFM writer.
static bool writePfm(const std::string& path, const Image& image)
{
    std::ofstream out(path, std::ios::binary);
    out << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
    for (int y = image.height - 1; y >= 0; --y)
        out.write(reinterpret_cast<const char*>(&image.rgb[size_t(y) * image.width * 3]),
                  std::streamsize(sizeof(float) * 3 * image.width));
    return bool(out);
}

bool haveImageLibrary()
{
#ifdef WAVEVCM_HAVE_OIIO
    return true;
#else
    return false;
#endif
}

#ifndef WAVEVCM_HAVE_OIIO
[[noreturn]] static void noImageLibrary(const std::string& path)
{
    throw Error(path + ": this wavevcm was built without OpenImageIO (-DWAVEVCM_IMAGE_IO=OFF): it writes .pfm "
                       "images only and reads none");
}
#endif

void checkOutputFormat(const std::string& path)
{
    std::string ext = extensionOf(path);
    if (ext != ".exr" && ext != ".hdr" && ext != ".pfm" && ext != ".png" && ext != ".jpg" && ext != ".jpeg")
        throw Error(path + ": unsupported output format (use .exr, .hdr, .pfm, .png or .jpg)");
#ifndef WAVEVCM_HAVE_OIIO
    if (ext != ".pfm") noImageLibrary(path);
#endif
}

void writeImage(const std::string& path, const Image& image)
{
    checkOutputFormat(path);
    std::string ext = extensionOf(path);
    std::filesystem::path tmp = partialPath(path);
    if (ext == ".pfm") {
        if (!writePfm(tmp.string(), image)) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            throw Error(path + ": cannot write image");
        }
        commitPartial(tmp, path);
        return;
    }
#ifdef WAVEVCM_HAVE_OIIO
    bool eightBit = ext == ".png" || ext == ".jpg" || ext == ".jpeg";
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(spec, const_cast<float*>(image.rgb.data()));
    OIIO::ImageBuf out = buf;
    if (eightBit) {
        // Clamp to [0, 1] first; the sRGB curve is applied by OpenImageIO.
        out = OIIO::ImageBufAlgo::clamp(buf, 0.0f, 1.0f);
        out = OIIO::ImageBufAlgo::colorconvert(out, "linear", "sRGB");
        if (out.has_error()) throw Error(path + ": colour conversion failed: " + out.geterror());
    }
    if (!image.alpha.empty() && (ext == ".png" || ext == ".exr")) { // alpha as stored, never sRGB-encoded
        OIIO::ImageBuf alpha(OIIO::ImageSpec(image.width, image.height, 1, OIIO::TypeDesc::FLOAT),
                             const_cast<float*>(image.alpha.data()));
        out = OIIO::ImageBufAlgo::channel_append(out, OIIO::ImageBufAlgo::clamp(alpha, 0.0f, 1.0f));
        if (out.has_error()) throw Error(path + ": cannot add the alpha channel: " + out.geterror());
        out.specmod().channelnames = {"R", "G", "B", "A"};
        out.specmod().alpha_channel = 3;
    }
    if (!out.write(tmp.string(), eightBit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT)) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        std::string why = out.geterror();
        throw Error(path + ": cannot write image" + (why.empty() ? "" : ": " + why));
    }
    commitPartial(tmp, path);
#endif
}

void writeExrLayers(const std::string& path, const std::vector<std::string>& names, const std::vector<Image>& images)
{
    if (images.empty() || names.size() != images.size()) throw Error(path + ": no layers to write");
#ifndef WAVEVCM_HAVE_OIIO
    noImageLibrary(path);
#else
    int w = images[0].width, h = images[0].height, channels = int(3 * images.size());
    OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    for (const std::string& name : names)
        for (const char* c : {".R", ".G", ".B"}) spec.channelnames.push_back(name + c);
    std::vector<float> pixels(size_t(w) * h * channels);
    for (size_t l = 0; l < images.size(); ++l)
        for (size_t p = 0; p < size_t(w) * h; ++p)
            for (int c = 0; c < 3; ++c) pixels[p * channels + 3 * l + c] = images[l].rgb[3 * p + c];
    OIIO::ImageBuf buf(spec, pixels.data());
    std::filesystem::path tmp = partialPath(path);
    if (!buf.write(tmp.string(), OIIO::TypeDesc::FLOAT, "openexr")) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw Error(path + ": cannot write image: " + buf.geterror());
    }
    commitPartial(tmp, path);
#endif
}

Image readImage(const std::string& path)
{
    if (!std::filesystem::exists(path)) throw Error(path + ": no such file");
#ifndef WAVEVCM_HAVE_OIIO
    noImageLibrary(path);
#else
    OIIO::ImageBuf buf(path);
    if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) throw Error(path + ": cannot read image: " + buf.geterror());
    const OIIO::ImageSpec& spec = buf.spec();
    Image image(spec.width, spec.height);
    int channels = spec.nchannels;
    std::vector<float> pixels(size_t(spec.width) * spec.height * channels);
    if (!buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pixels.data()))
        throw Error(path + ": cannot read image: " + buf.geterror());
    for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
        for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = pixels[p * channels + std::min(c, channels - 1)];
    return image;
#endif
}

Image decodeImage(const unsigned char* data, size_t size, const std::string& name)
{
    // OpenImageIO picks the reader by file name: name the format the bytes start with.
    const char* format = nullptr;
    if (size >= 8 && std::memcmp(data, "\x89PNG\r\n\x1a\n", 8) == 0) format = "image.png";
    if (size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF) format = "image.jpg";
    if (size >= 12 && std::memcmp(data, "RIFF", 4) == 0 && std::memcmp(data + 8, "WEBP", 4) == 0)
        format = "image.webp"; // EXT_texture_webp
    if (!format) throw Error(name + ": not a PNG, JPEG or WebP image");
#ifndef WAVEVCM_HAVE_OIIO
    noImageLibrary(name);
#else
    OIIO::Filesystem::IOMemReader memory(const_cast<unsigned char*>(data), size);
    // Colour as stored: glTF's RGBA is not premultiplied, and OpenImageIO
    // would otherwise multiply colour by alpha on reading.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    void* proxy = &memory; // with a config, OpenImageIO takes the memory reader from it
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    auto input = OIIO::ImageInput::open(format, &config, &memory);
    if (!input) throw Error(name + ": cannot decode image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw Error(name + ": image has no pixels");
    std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
        throw Error(name + ": cannot decode image: " + input->geterror());
    Image image(spec.width, spec.height);
    int channels = spec.nchannels;
    for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
        for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = pixels[p * channels + (channels >= 3 ? c : 0)]; // grey(+alpha)
    if (channels == 2 || channels == 4) {
        image.alpha.resize(size_t(spec.width) * spec.height);
        for (size_t p = 0; p < image.alpha.size(); ++p) image.alpha[p] = pixels[p * channels + size_t(channels - 1)];
    }
    return image;
#endif
}

void srgbToLinear(Image& image)
{
    for (float& v : image.rgb)
        v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

ImageDifference compareImages(const Image& test, const Image& reference)
{
    if (test.width != reference.width || test.height != reference.height)
        throw Error("image sizes differ: " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                    " vs " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
    double se = 0, rel = 0, tonemapped = 0, sumTest = 0, sumRef = 0;
    size_t n = test.rgb.size();
    for (size_t i = 0; i < n; ++i) {
        double t = test.rgb[i], r = reference.rgb[i], d = t - r;
        se += d * d;
        rel += d * d / (r * r + 0.01);
        double dt = t / (1 + std::fabs(t)) - r / (1 + std::fabs(r));
        tonemapped += dt * dt;
        sumTest += t;
        sumRef += r;
    }
    ImageDifference out;
    out.rmse = std::sqrt(se / double(n));
    out.relMse = rel / double(n);
    out.tonemappedMse = tonemapped / double(n);
    out.meanRatio = sumRef > 0 ? sumTest / sumRef : (sumTest == 0 ? 1.0 : INFINITY);
    return out;
}

} // namespace wv
