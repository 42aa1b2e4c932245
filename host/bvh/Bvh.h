// Binned-SAH bounding volume hierarchy over triangles, built on the host and
// flattened depth-first into the BvhNode array the kernels traverse.
#pragma once

#include "../../kernels/interface/shared_types.h"
#include "../Vec3.h"

#include <cstdint>
#include <vector>

namespace wv {

struct Bvh {
    std::vector<BvhNode> nodes;
    // triangleOrder[i] is the scene triangle stored at BVH position i.
    std::vector<uint32_t> triangleOrder;
    int depth = 0;            // levels below the root; kernels keep a stack of BVH_STACK_SIZE
    double buildSeconds = 0;
};

// `vertices` holds three vertices per triangle. Throws if there are none.
Bvh buildBvh(const std::vector<Vec3>& vertices);

// The kernels' stack bound (kernels/geometry/bvh_traversal.h); the build stays within it.
constexpr int kMaxBvhDepth = 63;

} // namespace wv
