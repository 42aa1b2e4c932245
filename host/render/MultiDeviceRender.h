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

class MultiDeviceRender {
public:
    MultiDeviceRender(const std::vector<DeviceContext*>& devices, const Scene& scene, const Bvh& bvh,
                      const RenderSettings& settings);

    // After each iteration, on the thread of the device that ran it (calls
    // are serialized; their time is not render time): the renderer, and the
    // iterations and render seconds of the whole render so far.
    using IterationDone = std::function<void(Renderer&, int iterations, double seconds)>;

    // Renders until `iterations` in all (0: no limit), `seconds` of render
    // time (0: none) or `stop()`; whole iterations only, so the global
    // indices done are 0 … iterations() − 1. An exception on any device ends
    // the render on all of them and is rethrown here.
    void run(int iterations, double seconds, const std::function<bool()>& stop, const IterationDone& done);

    int iterations() const;
    double seconds() const { return seconds_; } // render time of run()
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
};

} // namespace wv
