// One image rendered on several OpenCL devices at once: a Renderer per
// device, each taking the next global iteration index when it finishes one,
// so that a fast device does more of the work than a slow one. Iterations of
// every algorithm are independent (their random numbers and merge radius
// depend on the global index only), so the result is the image of one device
// running the same iterations, up to float rounding; the images are summed,
// weighted by each device's iteration count. With one device it renders in
// the calling thread, exactly as a lone Renderer.
#pragma once

#include "Renderer.h"

#include <functional>
#include <memory>
#include <vector>

namespace wv {

// The global iteration indices one process renders: first, first + stride,
// first + 2·stride, … below `end` (0: no end). A lone process renders 0, 1,
// 2, …; rank r of an MPI job of K ranks r, r + K, r + 2K, … (host/cluster).
struct IterationSchedule {
    int first = 0, stride = 1, end = 0;
    // How many indices the schedule has (-1: no end).
    int count() const { return end <= 0 ? -1 : (end > first ? (end - first + stride - 1) / stride : 0); }
};

// The OpenCL contexts of a render's devices (whole devices, or the
// pipelines pipelineDevices makes of one), owned together, and the pointers
// MultiDeviceRender takes.
struct DeviceContexts {
    explicit DeviceContexts(const std::vector<DeviceInfo>& devices, bool profiling = false)
    {
        for (const DeviceInfo& d : devices) {
            owned.push_back(std::make_unique<DeviceContext>(d, profiling));
            pointers.push_back(owned.back().get());
        }
    }
    std::vector<std::unique_ptr<DeviceContext>> owned;
    std::vector<DeviceContext*> pointers;
};

class MultiDeviceRender {
public:
    // trees: the scene's BVH for each device's packet width (buildBvhs).
    MultiDeviceRender(const std::vector<DeviceContext*>& devices, const Scene& scene, const std::vector<Bvh>& trees,
                      const RenderSettings& settings);

    // After each iteration, on the thread of the device that ran it (calls
    // are serialized; their time is not render time, except for the share
    // the other renderers spend rendering meanwhile: with K renderers 1/K of
    // it is excluded): the renderer, and the iterations and render seconds
    // of this MultiDeviceRender so far (all calls of run()).
    using IterationDone = std::function<void(Renderer&, int iterations, double seconds)>;

    // Renders the schedule's next indices, one per iteration, until it has no
    // more, `seconds` of render time in this call (0: no limit) or `stop()`;
    // whole iterations only. A later call goes on where this one stopped, so
    // the indices done are always the schedule's first iterations(). An
    // exception on any device ends the render on all of them (the others'
    // iterations in flight are dropped at their next round) and is rethrown
    // here. `abandon` (optional, asked like `stop`, but also between the
    // rounds of an iteration) drops the iterations in flight unfinished.
    void run(const IterationSchedule& schedule, double seconds, const std::function<bool()>& stop,
             const IterationDone& done, const std::function<bool()>& abandon = nullptr);

    // Inside an IterationDone callback: the image of every iteration
    // finished so far, from `finished`'s image now (its iteration is done)
    // and each other renderer's as it was when that one last finished an
    // iteration (it may be in the middle of one now). Reads back one image.
    Image runningImage(Renderer& finished);
    // The iterations the last runningImage() holds: the callback's count when
    // it is called from every callback.
    int runningIterations() const;

    int iterations() const;
    double seconds() const { return seconds_; } // render time of every run() so far
    Image image();
    std::array<Image, 3> techniqueImages(); // RenderSettings::techniques
    uint64_t nonFiniteCount();
    uint64_t raysTraced() const;

    size_t deviceCount() const { return renderers_.size(); }
    Renderer& renderer(size_t i) { return *renderers_[i]; }
    const DeviceContext& device(size_t i) const { return *devices_[i]; }

private:
    std::vector<DeviceContext*> devices_;
    std::vector<std::unique_ptr<Renderer>> renderers_;
    double seconds_ = 0;
    // runningImage(): each renderer's image and iterations when it last
    // finished one.
    std::vector<Image> lastImages_;
    std::vector<int> lastIterations_;
};

} // namespace wv
