#include "PathState.h"

#include "SceneBuffers.h"

namespace wv {

// Two regions of path state, one per round parity (kernels/transport/path_state.h).
constexpr size_t kRegions = 2;

size_t PathState::bytesPerPath()
{
#define WV_FIELD_BYTES(space, type, name, perSlot) +size_t(perSlot) * sizeof(type)
    size_t pathBytes = 0 PATH_STATE_BUFFERS(WV_FIELD_BYTES);
    size_t queueBytes = 0 QUEUE_BUFFERS(WV_FIELD_BYTES);
#undef WV_FIELD_BYTES
    return kRegions * pathBytes + queueBytes;
}

PathState::PathState(DeviceContext& device, int capacity_, KernelBuffers& buffers) : capacity(capacity_)
{
    size_t n = size_t(capacity);
#define WV_ALLOCATE_FIELD(space, type, name, perSlot, slots)                                                     \
    if (perSlot > 0) {                                                                                          \
        buffers.name = deviceBuffer(device, slots * perSlot * sizeof(type), "the path state (" #name ")");      \
        bytes += slots * perSlot * sizeof(type);                                                                \
    }
#define WV_ALLOCATE_PATH_FIELD(space, type, name, perSlot) WV_ALLOCATE_FIELD(space, type, name, perSlot, kRegions * n)
#define WV_ALLOCATE_QUEUE(space, type, name, perSlot) WV_ALLOCATE_FIELD(space, type, name, perSlot, n)
    PATH_STATE_BUFFERS(WV_ALLOCATE_PATH_FIELD)
    QUEUE_BUFFERS(WV_ALLOCATE_QUEUE)
#undef WV_ALLOCATE_QUEUE
#undef WV_ALLOCATE_PATH_FIELD
#undef WV_ALLOCATE_FIELD
    buffers.queueCounters = deviceBuffer(device, kCounterBytes, "the queue counters");
    bytes += kCounterBytes;
}

} // namespace wv
