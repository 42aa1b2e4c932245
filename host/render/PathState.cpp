#include "PathState.h"

#include "SceneBuffers.h"

#include <numeric>
#include <vector>

namespace wv {

size_t PathState::bytesPerPath()
{
    return 0
#define WV_FIELD_BYTES(space, type, name, perSlot) +size_t(perSlot) * sizeof(type)
        PATH_STATE_BUFFERS(WV_FIELD_BYTES)
#undef WV_FIELD_BYTES
        + sizeof(int); // slotIndices
}

PathState::PathState(DeviceContext& device, int capacity_, KernelBuffers& buffers) : capacity(capacity_)
{
    size_t n = size_t(capacity);
#define WV_ALLOCATE_FIELD(space, type, name, perSlot)                                                            \
    if (perSlot > 0) {                                                                                          \
        buffers.name = deviceBuffer(device, n * perSlot * sizeof(type), "the path state (" #name ")");          \
        bytes += n * perSlot * sizeof(type);                                                                    \
    }
    PATH_STATE_BUFFERS(WV_ALLOCATE_FIELD)
#undef WV_ALLOCATE_FIELD
    std::vector<int> indices(n);
    std::iota(indices.begin(), indices.end(), 0);
    slotIndices = uploadBuffer(device, indices.data(), n * 4, "the slot indices");
    bytes += n * 4;
    buffers.queueCounters = deviceBuffer(device, kCounterBytes, "the queue counters");
    bytes += kCounterBytes;
}

} // namespace wv
