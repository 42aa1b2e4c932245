#include "EnvironmentLight.h"

#include "../Error.h"

#include <cmath>

namespace wv {

static double luminance(const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// Running sums of `values` scaled to end at 1 (uniform where they sum to 0).
static void appendCdf(const std::vector<double>& values, std::vector<float>& cdf)
{
    double total = 0;
    for (double v : values) total += v;
    double running = 0;
    cdf.push_back(0.0f);
    for (size_t i = 0; i < values.size(); ++i) {
        running += total > 0 ? values[i] : 1.0;
        cdf.push_back(float(running / (total > 0 ? total : double(values.size()))));
    }
    cdf.back() = 1.0f;
}

EnvironmentLight buildEnvironmentLight(const EnvironmentMap& map)
{
    EnvironmentLight e;
    e.width = map.image.width;
    e.height = map.image.height;
    if (e.width <= 0 || e.height <= 0 || map.image.rgb.empty())
        throw Error(map.path + ": the environment map has no texels");
    const double pi = M_PI;
    size_t texels = size_t(e.width) * size_t(e.height);
    e.radiance.resize(4 * texels);
    std::vector<double> rowSums(size_t(e.height));
    std::vector<double> f(size_t(e.width));
    double fSum = 0;
    for (int y = 0; y < e.height; ++y) {
        double theta0 = pi * y / e.height, theta1 = pi * (y + 1) / e.height;
        double sinCentre = std::sin(0.5 * (theta0 + theta1));
        double texelSolidAngle = 2 * pi / e.width * (std::cos(theta0) - std::cos(theta1));
        for (int x = 0; x < e.width; ++x) {
            const float* c = &map.image.rgb[3 * (size_t(y) * e.width + x)];
            float* r = &e.radiance[4 * (size_t(y) * e.width + x)];
            for (int k = 0; k < 3; ++k) {
                if (!std::isfinite(c[k]))
                    throw Error(map.path + ": texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") of the environment map is not finite");
                r[k] = std::max(0.0f, c[k]); // no negative radiance
            }
            r[3] = 0;
            double lum = luminance(r);
            f[size_t(x)] = lum * sinCentre;
            e.luminanceIntegral += lum * texelSolidAngle;
        }
        appendCdf(f, e.conditionalCdf);
        for (double v : f) rowSums[size_t(y)] += v;
        fSum += rowSums[size_t(y)];
    }
    appendCdf(rowSums, e.marginalCdf);
    // f / (mean f) is the density over the unit square of (u, v).
    e.pdfScale = fSum > 0 ? float(double(texels) / fSum) : 0.0f;
    return e;
}

} // namespace wv
