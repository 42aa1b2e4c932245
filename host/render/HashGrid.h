// The hash grid over light vertices for vertex merging, built on the device
// each iteration (kernels/stages/hash_grid.cl, kernels/transport/hash_grid.h): a counting
// sort of the vertices into buckets of hashed 2r-cells.
#pragma once

#include "../../kernels/interface/shared_types.h"
#include "../cl/DeviceContext.h"
#include "KernelProfile.h"

#include <cstdint>
#include <string>
#include <vector>

namespace wv {

class HashGrid {
public:
    // `program` holds the kernels of hash_grid.cl; `profile`, if not null,
    // records their launches.
    HashGrid(DeviceContext& device, const cl::Program& program, KernelProfile* profile = nullptr);

    // Room for `vertices` vertices, with one bucket per vertex on average
    // (SmallVCM), a power of two.
    void reserve(size_t vertices);

    // Device bytes per vertex of capacity: its MergeVertex, its bucket and
    // place in it, and up to two buckets' starts.
    static constexpr size_t kBytesPerVertex = sizeof(MergeVertex) + 2 * sizeof(int) + 2 * sizeof(int);

    // Enqueues the build over vertices[0, count) of the light-vertex buffer
    // (the program's StoredLightVertex records: LightVertex under
    // VERTEX_CONNECTION, else MergeVertex) for query radius `radius`.
    void build(const cl::Buffer& vertices, int count, float radius);

    const cl::Buffer& bucketStarts() const { return bucketStarts_; }     // int[buckets + 1]
    const cl::Buffer& bucketVertices() const { return bucketVertices_; } // MergeVertex[vertices], same order
    uint32_t buckets() const { return buckets_; }

    // The names of hash_grid.cl's kernels.
    static const std::vector<std::string>& kernelNames();

private:
    void launch(cl::Kernel& kernel, size_t items);

    DeviceContext& device_;
    KernelProfile* profile_;
    cl::Kernel count_, scanChunks_, scanTotals_, scanAdd_, scatter_;
    cl::Buffer bucketStarts_, vertexPlaces_, bucketVertices_, chunkTotals_;
    uint32_t buckets_ = 0;
    size_t capacity_ = 0;
};

} // namespace wv
