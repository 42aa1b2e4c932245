// The same rays traced with Embree (when the build found it), so the
// benchmarks can show how far wavevcm's traversal is from the best CPU ray
// tracer on this machine. Optional: the build works without Embree.
#pragma once

#include "Vec3.h"

#include <array>
#include <vector>

namespace wv {

using Float4 = std::array<float, 4>;

class EmbreeReference {
  public:
    // triangleVertices: three per triangle (Scene::vertices).
    explicit EmbreeReference(const std::vector<Vec3>& triangleVertices);
    ~EmbreeReference();
    EmbreeReference(const EmbreeReference&) = delete;
    EmbreeReference& operator=(const EmbreeReference&) = delete;

    // Traces every ray (origin.xyz; direction.xyz, tMax in direction.w) with
    // single-ray queries on every CPU the process may use. Closest hit:
    // (*t)[i] is the hit distance or INFINITY. Any hit: 0 if occluded,
    // INFINITY if not. Returns the wall seconds the queries took.
    double trace(const std::vector<Float4>& origins, const std::vector<Float4>& directions, bool anyHit,
                 std::vector<float>* t) const;

  private:
    struct Impl;
    Impl* impl_;
};

} // namespace wv
