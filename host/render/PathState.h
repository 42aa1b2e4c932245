// Device buffers for one wavefront of paths, structure of arrays (one buffer
// per field, indexed by path slot), plus the work queues
// (kernels/queue_ids.h). Sized by the wavefront capacity, independent of the
// image size.
#pragma once

#include "../../kernels/queue_ids.h"
#include "../cl/DeviceContext.h"

namespace wv {

constexpr size_t kCounterBytes = COUNTER_COUNT * COUNTER_STRIDE * sizeof(int);

struct PathState {
    int capacity = 0;
    cl::Buffer rayOrigins;        // float4
    cl::Buffer rayDirections;     // float4, w = tMax
    cl::Buffer pathPixel;         // int: the pixel (= sample) the path belongs to
    cl::Buffer pathDepth;         // int: segments so far, the camera segment included
    cl::Buffer pathThroughput;    // float4
    cl::Buffer pathPrevPdf;       // float: solid-angle pdf of the last BSDF sample, 0 = delta or camera (pt)
    cl::Buffer pathMis;           // float4: dVCM, dVC, dVM (bidirectional; kernels/mis.h)
    cl::Buffer pathFlags;         // int: PATH_* bits (kernels/path_state.h)
    cl::Buffer pathLastVertex;    // int: the light path's last stored vertex
    cl::Buffer hitT;              // float
    cl::Buffer hitTriangle;       // int
    cl::Buffer hitBary;           // float2
    cl::Buffer shadowOrigins;     // float4
    cl::Buffer shadowDirections;  // float4, w = tMax
    cl::Buffer shadowContribution;// float4
    cl::Buffer shadowPixel;       // int: where a light-tracing shadow ray splats
    cl::Buffer queueItems;        // int[QUEUE_COUNT × capacity]
    cl::Buffer counters;          // int[COUNTER_COUNT × COUNTER_STRIDE]
    cl::Buffer slotIndices;       // int[capacity] = 0, 1, 2, ...: the initial free queue
    size_t bytes = 0;

    PathState(DeviceContext& device, int capacity);

    // Bytes of device memory per path slot, for sizing the wavefront.
    static size_t bytesPerPath();
};

} // namespace wv
