#include "MultiDeviceRender.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

namespace wv {

MultiDeviceRender::MultiDeviceRender(const std::vector<DeviceContext*>& devices, const Scene& scene,
                                     const std::vector<Bvh>& trees, const RenderSettings& settings)
    : devices_(devices)
{
    for (DeviceContext* d : devices)
        renderers_.push_back(std::make_unique<Renderer>(*d, scene, bvhFor(trees, d->info), settings));
}

void MultiDeviceRender::run(const IterationSchedule& schedule, double seconds, const std::function<bool()>& stop,
                            const IterationDone& done, const std::function<bool()>& abandon)
{
    using clock = std::chrono::steady_clock;
    // Every entry handed out is rendered (or the render fails, or it is
    // abandoned, and the render ends): the entries done so far are the
    // schedule's first iterations().
    std::atomic<int> next{iterations()}, finished{iterations()};
    const double before = seconds_;
    std::atomic<bool> failed{false};
    std::mutex callback;
    std::exception_ptr error;
    // Callback time is not render time, but while one renderer is in the
    // callback the others go on rendering: 1/renderers of it is excluded
    // (all of it for a lone renderer). Under `callback`.
    double excluded = 0;
    const double excludedShare = 1.0 / double(renderers_.size());
    const clock::time_point start = clock::now();
    auto renderSeconds = [&] { return std::chrono::duration<double>(clock::now() - start).count() - excluded; };

    auto work = [&](Renderer& renderer) {
        try {
            for (;;) {
                {
                    std::lock_guard<std::mutex> lock(callback);
                    if (failed || stop() || (seconds > 0 && renderSeconds() >= seconds)) return;
                }
                int entry = next.fetch_add(1);
                if (schedule.count() >= 0 && entry >= schedule.count()) return;
                // Between rounds: a failure on another renderer, or `abandon`,
                // drops this iteration.
                std::function<bool()> abandonIteration;
                if (abandon || renderers_.size() > 1)
                    abandonIteration = [&] {
                        std::lock_guard<std::mutex> lock(callback);
                        return failed || (abandon && abandon());
                    };
                if (!renderer.iterate(schedule.first + entry * schedule.stride, abandonIteration)) return;
                std::lock_guard<std::mutex> lock(callback);
                if (failed) return;
                int all = ++finished;
                clock::time_point callbackStart = clock::now();
                double now = before + renderSeconds();
                if (done) done(renderer, all, now);
                excluded += excludedShare * std::chrono::duration<double>(clock::now() - callbackStart).count();
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(callback);
            if (!failed) error = std::current_exception();
            failed = true;
        }
    };
    if (renderers_.size() == 1) {
        work(*renderers_[0]);
    } else {
        std::vector<std::thread> threads;
        for (auto& r : renderers_) threads.emplace_back(work, std::ref(*r));
        for (std::thread& t : threads) t.join();
    }
    seconds_ += renderSeconds();
    if (error) std::rethrow_exception(error);
}

int MultiDeviceRender::iterations() const
{
    int n = 0;
    for (const auto& r : renderers_) n += r->iterations();
    return n;
}

uint64_t MultiDeviceRender::raysTraced() const
{
    uint64_t n = 0;
    for (const auto& r : renderers_) n += r->raysTraced();
    return n;
}

uint64_t MultiDeviceRender::nonFiniteCount()
{
    uint64_t n = 0;
    for (auto& r : renderers_) n += r->nonFiniteCount();
    return n;
}

// Each renderer's image is the mean of its iterations: weighted by their
// counts, in double.
static Image weightedMean(const std::vector<Image>& images, const std::vector<int>& counts)
{
    Image out(images[0].width, images[0].height);
    double total = 0;
    for (int c : counts) total += c;
    if (total == 0) return out;
    for (size_t i = 0; i < out.rgb.size(); ++i) {
        double sum = 0;
        for (size_t d = 0; d < images.size(); ++d) sum += double(images[d].rgb[i]) * counts[d];
        out.rgb[i] = float(sum / total);
    }
    return out;
}

Image MultiDeviceRender::image()
{
    if (renderers_.size() == 1) return renderers_[0]->image();
    std::vector<Image> images;
    std::vector<int> counts;
    for (auto& r : renderers_) {
        images.push_back(r->image());
        counts.push_back(r->iterations());
    }
    return weightedMean(images, counts);
}

Image MultiDeviceRender::runningImage(Renderer& finished)
{
    if (renderers_.size() == 1) return finished.image();
    Image now = finished.image();
    lastImages_.resize(renderers_.size());
    lastIterations_.resize(renderers_.size(), 0);
    for (size_t i = 0; i < renderers_.size(); ++i) {
        if (renderers_[i].get() == &finished) {
            lastImages_[i] = now;
            lastIterations_[i] = finished.iterations();
        } else if (lastIterations_[i] == 0) {
            lastImages_[i] = Image(now.width, now.height); // weight 0 until it finishes one
        }
    }
    return weightedMean(lastImages_, lastIterations_);
}

int MultiDeviceRender::runningIterations() const
{
    if (renderers_.size() == 1) return renderers_[0]->iterations();
    int n = 0;
    for (int c : lastIterations_) n += c;
    return n;
}

std::array<Image, 3> MultiDeviceRender::techniqueImages()
{
    if (renderers_.size() == 1) return renderers_[0]->techniqueImages();
    std::array<std::vector<Image>, 3> families;
    std::vector<int> counts;
    for (auto& r : renderers_) {
        std::array<Image, 3> f = r->techniqueImages();
        for (int k = 0; k < 3; ++k) families[size_t(k)].push_back(f[size_t(k)]);
        counts.push_back(r->iterations());
    }
    std::array<Image, 3> out;
    for (int k = 0; k < 3; ++k)
        if (families[size_t(k)][0].width > 0) out[size_t(k)] = weightedMean(families[size_t(k)], counts);
    return out;
}

} // namespace wv
