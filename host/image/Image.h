// RGB float images: reading and writing through OpenImageIO, and the error
// metrics of `wavevcm compare`. A build without OpenImageIO
// (-DWAVEVCM_IMAGE_IO=OFF, for machines that lack it: the GPU kit) writes
// .pfm only and reads nothing; the other calls throw wv::Error saying so.
#pragma once

#include <string>
#include <vector>

namespace wv {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb; // width × height × 3, row 0 at the top, linear radiance
    std::vector<float> alpha; // width × height where the image has an alpha channel (textures), else empty

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
};

// By extension: .exr (32-bit float, linear), .hdr, .pfm (float), .png/.jpg
// (8-bit, sRGB-encoded); .png and .exr with the alpha channel if the image has one. Written to a temporary name beside `path` and renamed,
// so a failed or interrupted write never leaves a partial file.
void writeImage(const std::string& path, const Image& image);

// Throws wv::Error naming `path` unless writeImage can write its format:
// checked before a render, as checkWritable.
void checkOutputFormat(const std::string& path);

// Whether this build reads and writes images through OpenImageIO.
bool haveImageLibrary();

// One OpenEXR file (32-bit float) with each image as a layer of channels
// "<name>.R", "<name>.G", "<name>.B". Same temporary-name rule as writeImage.
void writeExrLayers(const std::string& path, const std::vector<std::string>& names, const std::vector<Image>& images);

// Throws wv::Error (naming the file and why) unless a file can be created
// beside `path`, and `path` itself is neither a directory nor read-only:
// checked before a render, so that a long render does not end at an
// unwritable path.
void checkWritable(const std::string& path);

// Any format OpenImageIO reads; the first three channels (grey is replicated).
Image readImage(const std::string& path);

// A PNG or JPEG file's bytes held in memory (a glTF image), decoded: its
// values as stored (sRGB-encoded for colour), in [0, 1], with its alpha
// channel if it has one (grey + alpha, RGBA). `name` names it in errors.
Image decodeImage(const unsigned char* data, size_t size, const std::string& name);

// The sRGB transfer function's inverse, per channel (textures' colours).
void srgbToLinear(Image& image);

struct ImageDifference {
    double rmse = 0;      // sqrt(mean over pixels and channels of (t − r)²)
    double relMse = 0;    // mean of (t − r)² / (r² + 0.01), per channel
    double meanRatio = 0; // mean(test) / mean(reference)
    // mean of (t/(1+|t|) − r/(1+|r|))², per channel: the error of
    // tone-mapped values, which a few fireflies do not dominate as they do relMSE
    double tonemappedMse = 0;
};

// Throws wv::Error if the sizes differ.
ImageDifference compareImages(const Image& test, const Image& reference);

} // namespace wv
