#include "TechniqueImages.h"

#include <algorithm>

namespace wv {

void writeTechniqueImages(const std::string& stem, const std::array<Image, 3>& families)
{
    writeExrLayers(stem + ".techniques.exr", {"unidirectional", "connection", "merging"},
                   {families[0], families[1], families[2]});
    Image shares(families[0].width, families[0].height);
    for (size_t p = 0; p < shares.rgb.size() / 3; ++p) {
        float lum[3], total = 0;
        for (int f = 0; f < 3; ++f) {
            const float* c = &families[f].rgb[3 * p];
            lum[f] = std::max(0.0f, 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]);
            total += lum[f];
        }
        for (int f = 0; f < 3; ++f) shares.rgb[3 * p + f] = total > 0 ? lum[f] / total : 0.0f;
    }
    writeImage(stem + ".techniques.png", shares);
}

} // namespace wv
