#include "../Error.h"
#include "../image/Image.h"
#include "Commands.h"

#include <cstdio>

namespace wv {

int runCompare(const std::string& test, const std::string& reference, double maxRelMse)
{
    Image t = readImage(test), r = readImage(reference);
    if (t.width != r.width || t.height != r.height)
        throw Error(test + " is " + std::to_string(t.width) + "x" + std::to_string(t.height) + " but " + reference +
                    " is " + std::to_string(r.width) + "x" + std::to_string(r.height));
    ImageDifference d = compareImages(t, r);
    std::printf("rmse %.6g\nrelmse %.6g\nmean_ratio %.6g\ntonemapped_mse %.6g\n", d.rmse, d.relMse, d.meanRatio,
                d.tonemappedMse);
    if (maxRelMse >= 0 && !(d.relMse <= maxRelMse)) {
        std::fprintf(stderr, "wavevcm: relMSE %.6g exceeds the bound %.6g\n", d.relMse, maxRelMse);
        return 1;
    }
    return 0;
}

} // namespace wv
