// Helpers for the tests that render: scenes built in code, rendering a few
// iterations on a device, and comparing images tile by tile statistically.
#pragma once

#include "bvh/Bvh.h"
#include "cl/DeviceContext.h"
#include "cl/Devices.h"
#include "image/Image.h"
#include "render/Algorithm.h"
#include "scene/Scene.h"

#include <cstdint>
#include <vector>

namespace wv::test {

// A UV sphere; `inward` winds the triangles so the front face (and the
// geometric normal) looks at the centre.
void addSphere(Scene& s, Vec3 centre, float radius, bool inward, int material, int rings = 24, int segments = 48);

// Flat vertex normals for the triangles added after the scene's last
// normals (a scene with vertex normals needs them for every triangle).
void addFlatNormals(Scene& s);

Material lambert(float albedo, float emission = 0);
Material smoothGlass(float ior = 1.5f);

struct Render {
    Image image;
    uint64_t nonFinite = 0;
};

// Mean over an image's pixels and channels, and its standard error from the
// spread of the pixel values (for an image that is uniform in expectation,
// whose pixels are independent samples of it; a pixel's channels are
// correlated, so pixels are counted, not values).
void meanAndStandardError(const Image& image, double* mean, double* se);

// A furnace's check of a render whose image is uniform in expectation: its
// mean within 5 standard errors of `expected` (a false alarm ~6e-7), the
// standard error below maxRelativeError · expected (so that any error above
// 5 · maxRelativeError · expected fails, and smaller ones where the render
// is less noisy than that bound), and no non-finite sample.
void expectMean(const Render& r, double expected, double maxRelativeError);

// `iterations` iterations of `algorithm` at width × height with a small
// wavefront (several rounds of slot regeneration per iteration), on an
// existing context and tree (renderSeeds shares them between its seeds: a
// context and the scene's tree per render cost the seed loops of the
// convergence tests a share of their time). radiusFactor: the merge radius
// (RenderSettings).
Render renderOn(DeviceContext& device, const Scene& scene, const Bvh& bvh, Algorithm algorithm, int width,
                int height, int iterations, uint32_t seed, int maxPathLength = 10, float radiusFactor = 0.003f);

// The one context of a device in this test process, which render() and
// renderSeeds() use: renderers in it share each program build
// (buildProgramOnce), where a new context reloads a program from the
// driver's cache (~1 s on PoCL).
DeviceContext& sharedContext(const DeviceInfo& info);

// The same on the device's shared context, over the tree the device's packet
// width gets in a render (trianglePacketWidth).
Render render(const DeviceInfo& device, const Scene& scene, Algorithm algorithm, int width, int height,
              int iterations, uint32_t seed, int maxPathLength = 10, float radiusFactor = 0.003f);

// Renders of one configuration with seeds 1..seeds.
std::vector<Image> renderSeeds(const DeviceInfo& device, const Scene& scene, Algorithm algorithm, int width,
                               int height, int iterations, int seeds, int maxPathLength = 10,
                               float radiusFactor = 0.003f);

// Compares two estimators of the same image, each given as renders with
// independent seeds: per tile × tile pixel block, the difference of the mean
// over seeds must stay within `k` standard errors, estimated from the
// seed-to-seed spread of each side. `mask` (per pixel, optional) excludes
// pixels; blocks with fewer than half their pixels left are skipped.
// Returns the number of blocks that disagree (each also reported as a
// test failure) and sets *compared to the number of blocks compared.
int tilesDisagreeing(const std::vector<Image>& a, const std::vector<Image>& b, int tile, double k,
                     const std::vector<bool>& mask = {}, int* compared = nullptr);

// pt, bpt and vcm, which weight the techniques differently, render `scene`
// alike at 32×32: per 8×8 block, the means over 6 seeds agree within 5
// seed-to-seed standard errors (tilesDisagreeing; a false alarm ~6e-7 per
// block), bpt and vcm at 16 iterations, pt at ptIterationFactor × 16 (more
// where its estimator has a heavy tail the others do not).
void expectPtBptVcmAgree(const Scene& scene, int ptIterationFactor);

// The mean of channel c over the block × block pixels from (x0, y0) of a
// size × size image, and its standard error from the pixels' spread.
double blockMean(const Image& image, int size, int x0, int y0, int block, int c, double* se);

// Each of `algorithms`, rendered like `reference` (renderSeeds with `seeds`
// seeds at width × height, `iterations` each), agrees with it on every 8×8
// block within 5 seed-to-seed standard errors, and every block is compared.
void expectConvergeTo(const DeviceInfo& device, const Scene& scene, const std::vector<Image>& reference,
                      std::vector<Algorithm> algorithms, int width, int height, int iterations, int seeds);

// The same image from every OpenCL device present (skips with one): per 8×8
// block, means over three seeds agree within 5 seed-to-seed standard errors;
// with the same seeds the devices draw the same samples, so their images must
// also be much closer to each other than two seeds are.
void expectSameImageOnEveryDevice(const Scene& scene, Algorithm algorithm, int size, int iterations);

} // namespace wv::test
