// Device buffers for one wavefront of paths, structure of arrays (one buffer
// per field, indexed by path slot), plus the work queues. Sized by the
// wavefront capacity, independent of the image size.
#pragma once

#include "../cl/DeviceContext.h"

namespace wv {

struct PathState {
    int capacity = 0;
    cl::Buffer rayOrigins;     // float4
    cl::Buffer rayDirections;  // float4, w = tMax
    cl::Buffer pathPixels;     // int, -1 = slot unused
    cl::Buffer hitT;           // float
    cl::Buffer hitTriangle;    // int, -1 = miss
    cl::Buffer hitBary;        // float2
    cl::Buffer sampleRadiance; // float4
    cl::Buffer queueItems;     // int, the ray queue
    cl::Buffer counters;       // int[COUNTER_COUNT] (kernels/queue_ids.h)
    size_t bytes = 0;

    PathState(DeviceContext& device, int capacity);

    // Bytes of device memory per path slot, for sizing the wavefront.
    static size_t bytesPerPath();
};

} // namespace wv
