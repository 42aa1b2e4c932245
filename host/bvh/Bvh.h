// Bounding volume hierarchy over triangles, built on the host: a binned-SAH
// binary tree collapsed into the wide BvhNode tree the kernels traverse, its
// leaves' triangles in TrianglePackets (kernels/interface/shared_types.h).
#pragma once

#include "../../kernels/interface/shared_types.h"
#include "../Vec3.h"

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace wv {

// The allocator of the build's large arrays. resize() leaves new elements
// default-initialized (for these plain structs: unwritten), so an array is not
// zero-filled by one thread before the build's threads write it; and arrays of
// 2 MiB or more are aligned for transparent huge pages, asked for where Linux
// grants them without compacting memory first (Bvh.cpp): they cut the page
// faults, one per 4 KiB page otherwise.
void* allocateLargeArray(size_t bytes); // freed by std::free; throws std::bad_alloc

template <typename T>
struct LargeArrayAllocator {
    using value_type = T;
    LargeArrayAllocator() = default;
    template <typename U>
    LargeArrayAllocator(const LargeArrayAllocator<U>&) noexcept
    {
    }
    T* allocate(size_t n) { return static_cast<T*>(allocateLargeArray(n * sizeof(T))); }
    void deallocate(T* p, size_t) noexcept { std::free(p); }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args)
    {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    template <typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value)
    {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U>
    bool operator==(const LargeArrayAllocator<U>&) const noexcept { return true; }
    template <typename U>
    bool operator!=(const LargeArrayAllocator<U>&) const noexcept { return false; }
};

template <typename T>
using LargeArray = std::vector<T, LargeArrayAllocator<T>>;

// A tree's triangle packets: four or eight triangles wide.
using TrianglePackets = std::variant<LargeArray<TrianglePacket4>, LargeArray<TrianglePacket8>>;

struct Bvh {
    LargeArray<BvhNode> nodes; // the root first
    TrianglePackets packets;
    // triangleOrder[i] is the scene triangle stored at BVH position i: the
    // same for either packet width (the binary tree does not depend on it).
    std::vector<uint32_t> triangleOrder;
    int depth = 0;          // levels of wide nodes
    int binaryHeight = 0;   // of the binary tree it was collapsed from (a leaf: 0)
    // Of the binary tree the wide one is collapsed from (leaves of at most
    // four triangles, or more where SAH says so), per ray into the root's
    // box: traversal step 1, triangle test 1.
    double sahCost = 0;
    double buildSeconds = 0;

    int packetWidth() const { return packets.index() == 0 ? 4 : 8; }
    size_t packetCount() const { return std::visit([](const auto& p) { return p.size(); }, packets); }
    size_t packetBytes() const
    {
        return std::visit([](const auto& p) { return p.size() * sizeof(p[0]); }, packets);
    }
    const void* packetData() const { return std::visit([](const auto& p) -> const void* { return p.data(); }, packets); }
};

// The binary tree's depth bound (BVH_STACK_SIZE in shared_types.h is the
// traversal stack): a tree this deep can be collapsed within the stack.
constexpr int kMaxBvhDepth = BVH_STACK_SIZE - 1;

// `vertices` holds three vertices per triangle; packetWidth is 4 or 8
// (TrianglePacket4, TrianglePacket8; a device's is trianglePacketWidth in
// render/SceneBuffers.h). Throws if there are no triangles.
// stackBudget: the most stack entries a traversal of the wide tree may hold;
// at least the binary tree's height (tests pass that height, so that the
// collapse must fall back to binary nodes where eight children would not fit).
Bvh buildBvh(const std::vector<Vec3>& vertices, int packetWidth = DEFAULT_TRIANGLE_PACKET_WIDTH,
             int stackBudget = kMaxBvhDepth);

// Appends the packets of BVH positions [begin, begin + count), in order, to
// `packets` (Packet: TrianglePacket4 or TrianglePacket8); the vertices of
// position i are vertices[3 · order[i] + k].
template <typename Packet>
void appendPackets(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order, uint32_t begin,
                   uint32_t count, std::vector<Packet>& packets);

} // namespace wv
