#include "HashGrid.h"

#include "SceneBuffers.h"

#include <algorithm>

namespace wv {

// Buckets per serially scanned chunk of the prefix sum.
static const uint32_t kScanChunk = 1024;
static const size_t kLocalSize = 64;

HashGrid::HashGrid(DeviceContext& device, const cl::Program& program, KernelProfile* profile)
    : device_(device), profile_(profile), count_(program, "grid_count"), scanChunks_(program, "scan_chunks"),
      scanTotals_(program, "scan_totals"), scanAdd_(program, "scan_add"), scatter_(program, "grid_scatter")
{
}

const std::vector<std::string>& HashGrid::kernelNames()
{
    static const std::vector<std::string> names = {"grid_count", "scan_chunks", "scan_totals", "scan_add",
                                                   "grid_scatter"};
    return names;
}

void HashGrid::reserve(size_t vertices)
{
    if (vertices <= capacity_) return;
    capacity_ = vertices;
    buckets_ = 1024;
    while (buckets_ < vertices && buckets_ < (1u << 30)) buckets_ *= 2;
    bucketStarts_ = deviceBuffer(device_, (size_t(buckets_) + 1) * sizeof(int), "the hash grid");
    vertexPlaces_ = deviceBuffer(device_, vertices * 2 * sizeof(int), "the hash grid");
    bucketVertices_ = deviceBuffer(device_, vertices * sizeof(MergeVertex), "the hash grid");
    chunkTotals_ = deviceBuffer(device_, (size_t(buckets_) / kScanChunk + 2) * sizeof(int), "the hash grid");
}

void HashGrid::launch(cl::Kernel& kernel, size_t items)
{
    size_t global = (std::max<size_t>(items, 1) + kLocalSize - 1) / kLocalSize * kLocalSize;
    cl::Event event;
    device_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(kLocalSize), nullptr,
                                       profile_ ? &event : nullptr);
    if (profile_) profile_->record(kernel, items, event);
}

template <typename... Args> static void setArgs(cl::Kernel& kernel, const Args&... args)
{
    cl_uint index = 0;
    (kernel.setArg(index++, args), ...);
}

void HashGrid::build(const cl::Buffer& vertices, int count, float radius)
{
    count = int(std::min(size_t(std::max(count, 0)), capacity_));
    float cellSize = 2.0f * radius;
    int chunks = int((buckets_ + kScanChunk - 1) / kScanChunk);
    device_.queue.enqueueFillBuffer(bucketStarts_, 0, 0, (size_t(buckets_) + 1) * sizeof(int));
    setArgs(count_, vertices, count, cellSize, buckets_, bucketStarts_, vertexPlaces_);
    setArgs(scanChunks_, bucketStarts_, int(buckets_), int(kScanChunk), chunkTotals_, chunks);
    setArgs(scanTotals_, chunkTotals_, chunks);
    setArgs(scanAdd_, bucketStarts_, int(buckets_), int(kScanChunk), chunkTotals_);
    setArgs(scatter_, vertices, count, vertexPlaces_, bucketStarts_, bucketVertices_);
    if (count > 0) launch(count_, size_t(count));
    launch(scanChunks_, size_t(chunks));
    launch(scanTotals_, 1);
    launch(scanAdd_, size_t(buckets_) + 1);
    if (count > 0) launch(scatter_, size_t(count));
}

} // namespace wv
