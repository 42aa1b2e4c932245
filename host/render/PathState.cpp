#include "PathState.h"

#include "SceneBuffers.h"

#include <numeric>
#include <vector>

namespace wv {

size_t PathState::bytesPerPath(int regions)
{
#define WV_FIELD_BYTES(space, type, name, perSlot) +size_t(perSlot) * sizeof(type)
    size_t pathBytes = 0 PATH_STATE_BUFFERS(WV_FIELD_BYTES);
    size_t queueBytes = 0 QUEUE_BUFFERS(WV_FIELD_BYTES);
#undef WV_FIELD_BYTES
    return size_t(regions) * pathBytes + queueBytes + sizeof(int); // slotIndices
}

PathState::PathState(DeviceContext& device, int capacity_, int regions, KernelBuffers& buffers) : capacity(capacity_)
{
    size_t n = size_t(capacity);
#define WV_ALLOCATE_FIELD(space, type, name, perSlot, slots)                                                     \
    if (perSlot > 0) {                                                                                          \
        buffers.name = deviceBuffer(device, slots * perSlot * sizeof(type), "the path state (" #name ")");      \
        bytes += slots * perSlot * sizeof(type);                                                                \
    }
#define WV_ALLOCATE_PATH_FIELD(space, type, name, perSlot) WV_ALLOCATE_FIELD(space, type, name, perSlot, n * regions)
#define WV_ALLOCATE_QUEUE(space, type, name, perSlot) WV_ALLOCATE_FIELD(space, type, name, perSlot, n)
    PATH_STATE_BUFFERS(WV_ALLOCATE_PATH_FIELD)
    QUEUE_BUFFERS(WV_ALLOCATE_QUEUE)
#undef WV_ALLOCATE_QUEUE
#undef WV_ALLOCATE_PATH_FIELD
#undef WV_ALLOCATE_FIELD
    std::vector<int> indices(n);
    std::iota(indices.begin(), indices.end(), 0);
    slotIndices = uploadBuffer(device, indices.data(), n * 4, "the slot indices");
    bytes += n * 4;
    buffers.queueCounters = deviceBuffer(device, kCounterBytes, "the queue counters");
    bytes += kCounterBytes;
}

} // namespace wv
