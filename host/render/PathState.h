// Device buffers for one wavefront of paths: the path-state fields of
// kernels/interface/kernel_interface.h (structure of arrays, one buffer per field,
// indexed by path slot), the work queues (kernels/interface/queue_ids.h) and their
// counters. Sized by the wavefront capacity, independent of the image size;
// the path state in two regions of it, one per round parity
// (kernels/transport/path_state.h).
#pragma once

#include "../../kernels/interface/queue_ids.h"
#include "../cl/DeviceContext.h"
#include "KernelBindings.h"

namespace wv {

constexpr size_t kCounterBytes = COUNTER_COUNT * COUNTER_STRIDE * sizeof(int);

struct PathState {
    int capacity = 0;
    size_t bytes = 0;

    // Allocates every path-state field (two regions of `capacity` slots),
    // the queues and their counters into `buffers`.
    PathState(DeviceContext& device, int capacity, KernelBuffers& buffers);

    // Bytes of device memory per path slot of the wavefront, for sizing it.
    static size_t bytesPerPath();
};

} // namespace wv
