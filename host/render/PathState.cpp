#include "PathState.h"

#include "../../kernels/queue_ids.h"
#include "SceneBuffers.h"

#include <numeric>
#include <vector>

namespace wv {

// The per-slot element sizes, in the order of the members.
static const size_t kFieldBytes[] = {16, 16, 4, 4, 16, 4, 16, 4, 4, 4, 4, 8, 16, 16, 16, 4, 4 * QUEUE_COUNT, 4};

size_t PathState::bytesPerPath() { return std::accumulate(std::begin(kFieldBytes), std::end(kFieldBytes), size_t(0)); }

PathState::PathState(DeviceContext& device, int capacity_) : capacity(capacity_)
{
    size_t n = size_t(capacity);
    auto buffer = [&](size_t elementSize, const char* what) {
        bytes += n * elementSize;
        return deviceBuffer(device, n * elementSize, std::string("the path state (") + what + ")");
    };
    rayOrigins = buffer(16, "ray origins");
    rayDirections = buffer(16, "ray directions");
    pathPixel = buffer(4, "pixels");
    pathDepth = buffer(4, "depths");
    pathThroughput = buffer(16, "throughput");
    pathPrevPdf = buffer(4, "pdfs");
    pathMis = buffer(16, "MIS quantities");
    pathFlags = buffer(4, "flags");
    pathLastVertex = buffer(4, "last light vertices");
    hitT = buffer(4, "hit distances");
    hitTriangle = buffer(4, "hit triangles");
    hitBary = buffer(8, "barycentrics");
    shadowOrigins = buffer(16, "shadow ray origins");
    shadowDirections = buffer(16, "shadow ray directions");
    shadowContribution = buffer(16, "shadow ray contributions");
    shadowPixel = buffer(4, "splat pixels");
    queueItems = buffer(4 * QUEUE_COUNT, "queues");
    std::vector<int> indices(n);
    std::iota(indices.begin(), indices.end(), 0);
    slotIndices = uploadBuffer(device, indices.data(), n * 4, "the slot indices");
    bytes += n * 4;
    counters = deviceBuffer(device, kCounterBytes, "the queue counters");
    bytes += kCounterBytes;
}

} // namespace wv
