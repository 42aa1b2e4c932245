// The light transport algorithms `--algorithm` selects.
#pragma once

#include <string>

namespace wv {

enum class Algorithm { EyeLight, PathTracing, LightTracing, Bidirectional, ProgressivePhotonMapping,
                       BidirectionalPhotonMapping, VertexConnectionMerging };

// "el", "pt", ...; throws wv::Error for an unknown name.
Algorithm parseAlgorithm(const std::string& name);
std::string algorithmName(Algorithm a);

} // namespace wv
