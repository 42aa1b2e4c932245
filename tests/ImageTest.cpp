// Image files through OpenImageIO and the error metrics of `wavevcm compare`.
#include "Error.h"
#include "image/Image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace wv {
namespace {

Image gradient(int w, int h)
{
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img.rgb[3 * (size_t(y) * w + x) + c] = 0.01f * float(x + 2 * y + c) + 0.5f * float(c == 0 && y == 0);
    return img;
}

TEST(ImageFiles, FloatFormatsRoundTrip)
{
    Image img = gradient(13, 7);
    for (const char* ext : {".exr", ".pfm", ".hdr"}) {
        fs::path path = fs::temp_directory_path() / (std::string("wavevcm-roundtrip") + ext);
        writeImage(path.string(), img);
        Image back = readImage(path.string());
        ASSERT_EQ(back.width, 13);
        ASSERT_EQ(back.height, 7);
        // EXR and PFM store 32-bit floats exactly; RGBE (.hdr) stores 8 bits
        // per channel under an exponent shared by the pixel, so its error is
        // up to one step of 2^-7 of the pixel's largest channel (truncated mantissa).
        bool rgbe = std::string(ext) == ".hdr";
        for (size_t i = 0; i < img.rgb.size(); ++i) {
            size_t p = i / 3 * 3;
            float largest = std::max({img.rgb[p], img.rgb[p + 1], img.rgb[p + 2]});
            ASSERT_NEAR(back.rgb[i], img.rgb[i], rgbe ? largest / 128.0f : 0.0f) << ext << " value " << i;
        }
        fs::remove(path);
    }
}

TEST(ImageFiles, EightBitIsSrgbEncodedAndClamped)
{
    Image img(3, 1);
    img.rgb = {0.0f, 0.0f, 0.0f, 0.2140f, 0.2140f, 0.2140f, 5.0f, 5.0f, 5.0f}; // sRGB(0.214) ~ 0.5
    fs::path path = fs::temp_directory_path() / "wavevcm-srgb.png";
    writeImage(path.string(), img);
    Image back = readImage(path.string()); // OpenImageIO returns the stored code values / 255
    EXPECT_NEAR(back.rgb[0], 0.0f, 1e-6f);
    EXPECT_NEAR(back.rgb[3], 0.5f, 2.0f / 255.0f);
    EXPECT_NEAR(back.rgb[6], 1.0f, 1e-6f);
    fs::remove(path);
}

TEST(ImageFiles, ErrorsNameTheFile)
{
    Image img(2, 2);
    EXPECT_THROW(writeImage("/nonexistent-dir/x.exr", img), Error);
    EXPECT_THROW(writeImage("out.tiff-not", img), Error);
    try {
        readImage("/nonexistent-dir/missing.exr");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
    }
    // No partial file is left behind by a failed write.
    for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
        EXPECT_EQ(entry.path().filename().string().find(".x.exr.partial"), std::string::npos);
}

TEST(ImageMetrics, KnownDifferences)
{
    Image ref(4, 4), test(4, 4);
    std::fill(ref.rgb.begin(), ref.rgb.end(), 1.0f);
    std::fill(test.rgb.begin(), test.rgb.end(), 1.1f);
    ImageDifference d = compareImages(test, ref);
    EXPECT_NEAR(d.rmse, 0.1, 1e-6);
    EXPECT_NEAR(d.relMse, 0.01 / 1.01, 1e-6);
    EXPECT_NEAR(d.meanRatio, 1.1, 1e-6);
    EXPECT_NEAR(d.tonemappedMse, std::pow(1.1 / 2.1 - 0.5, 2), 1e-9);
    // A firefly: relMSE grows with its square, the tone-mapped error stays below 1 / pixels.
    test.rgb = ref.rgb;
    test.rgb[0] = 1e4f;
    d = compareImages(test, ref);
    EXPECT_GT(d.relMse, 1e5);
    EXPECT_LT(d.tonemappedMse, 0.25 / 48 + 1e-9);
    d = compareImages(ref, ref);
    EXPECT_EQ(d.rmse, 0.0);
    EXPECT_EQ(d.meanRatio, 1.0);
    EXPECT_THROW(compareImages(Image(4, 4), Image(4, 5)), Error);
}

} // namespace
} // namespace wv
