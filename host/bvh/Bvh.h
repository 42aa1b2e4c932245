// Bounding volume hierarchy over triangles, built on the host: a binned-SAH
// binary tree collapsed into the wide BvhNode tree the kernels traverse, its
// leaves' triangles in TrianglePackets (kernels/interface/shared_types.h).
#pragma once

#include "../../kernels/interface/shared_types.h"
#include "../Vec3.h"

#include <cstdint>
#include <vector>

namespace wv {

struct Bvh {
    std::vector<BvhNode> nodes; // the root first
    std::vector<TrianglePacket> packets;
    // triangleOrder[i] is the scene triangle stored at BVH position i.
    std::vector<uint32_t> triangleOrder;
    int depth = 0;          // levels of wide nodes
    double sahCost = 0;     // of the binary tree per ray into the root's box: traversal step 1, triangle test 1
    double buildSeconds = 0;
};

// `vertices` holds three vertices per triangle. Throws if there are none.
Bvh buildBvh(const std::vector<Vec3>& vertices);

// Appends packets of BVH positions [begin, begin + count), in order; the
// vertices of position i are vertices[3 · order[i] + k].
void appendPackets(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order, uint32_t begin,
                   uint32_t count, std::vector<TrianglePacket>& packets);

// The binary tree's depth bound (BVH_STACK_SIZE in shared_types.h is the
// traversal stack): a tree this deep can be collapsed within the stack.
constexpr int kMaxBvhDepth = BVH_STACK_SIZE - 1;

} // namespace wv
