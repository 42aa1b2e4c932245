#include "Algorithm.h"

#include "../Error.h"

namespace wv {

static const struct {
    Algorithm algorithm;
    const char* name;
} kNames[] = {{Algorithm::EyeLight, "el"},
              {Algorithm::PathTracing, "pt"},
              {Algorithm::LightTracing, "lt"},
              {Algorithm::Bidirectional, "bpt"},
              {Algorithm::ProgressivePhotonMapping, "ppm"},
              {Algorithm::BidirectionalPhotonMapping, "bpm"},
              {Algorithm::VertexConnectionMerging, "vcm"}};

Algorithm parseAlgorithm(const std::string& name)
{
    for (const auto& n : kNames)
        if (name == n.name) return n.algorithm;
    throw Error("unknown algorithm '" + name + "' (one of: el, pt, lt, bpt, ppm, bpm, vcm)");
}

std::string algorithmName(Algorithm a)
{
    for (const auto& n : kNames)
        if (a == n.algorithm) return n.name;
    return "?";
}

} // namespace wv
