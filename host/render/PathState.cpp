#include "PathState.h"

#include "../../kernels/queue_ids.h"
#include "SceneBuffers.h"

namespace wv {

size_t PathState::bytesPerPath()
{
    return 16 + 16 + 4 + 4 + 4 + 8 + 16 + 4;
}

PathState::PathState(DeviceContext& device, int capacity_) : capacity(capacity_)
{
    size_t n = size_t(capacity);
    auto buffer = [&](size_t elementSize, const char* what) {
        bytes += n * elementSize;
        return deviceBuffer(device, n * elementSize, std::string("the path state (") + what + ")");
    };
    rayOrigins = buffer(16, "ray origins");
    rayDirections = buffer(16, "ray directions");
    pathPixels = buffer(4, "pixels");
    hitT = buffer(4, "hit distances");
    hitTriangle = buffer(4, "hit triangles");
    hitBary = buffer(8, "barycentrics");
    sampleRadiance = buffer(16, "radiance");
    queueItems = buffer(4, "ray queue");
    counters = deviceBuffer(device, COUNTER_COUNT * sizeof(int), "the queue counters");
    bytes += COUNTER_COUNT * sizeof(int);
}

} // namespace wv
