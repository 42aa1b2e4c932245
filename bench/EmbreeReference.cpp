#include "EmbreeReference.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

#include <sched.h>

namespace wv {

struct EmbreeReference::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
};

EmbreeReference::EmbreeReference(const std::vector<Vec3>& triangleVertices) : impl_(new Impl)
{
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device) {
        delete impl_;
        throw std::runtime_error("Embree: rtcNewDevice failed (error " + std::to_string(int(rtcGetDeviceError(nullptr))) +
                                 ")");
    }
    impl_->scene = rtcNewScene(impl_->device);
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    size_t n = triangleVertices.size();
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), n));
    auto* index = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n / 3));
    for (size_t i = 0; i < n; ++i) {
        v[3 * i] = triangleVertices[i].x;
        v[3 * i + 1] = triangleVertices[i].y;
        v[3 * i + 2] = triangleVertices[i].z;
        index[i] = unsigned(i);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(impl_->scene);
    RTCError error = rtcGetDeviceError(impl_->device);
    if (error != RTC_ERROR_NONE) {
        rtcReleaseScene(impl_->scene);
        rtcReleaseDevice(impl_->device);
        delete impl_;
        throw std::runtime_error("Embree: building the scene failed (error " + std::to_string(int(error)) + ")");
    }
}

EmbreeReference::~EmbreeReference()
{
    rtcReleaseScene(impl_->scene);
    rtcReleaseDevice(impl_->device);
    delete impl_;
}

double EmbreeReference::trace(const std::vector<Float4>& origins, const std::vector<Float4>& directions, bool anyHit,
                              std::vector<float>* t) const
{
    size_t n = origins.size();
    t->assign(n, INFINITY);
    RTCScene scene = impl_->scene;
    auto work = [&](size_t begin, size_t end) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = begin; i < end; ++i) {
            RTCRayHit q;
            q.ray.org_x = origins[i][0];
            q.ray.org_y = origins[i][1];
            q.ray.org_z = origins[i][2];
            q.ray.dir_x = directions[i][0];
            q.ray.dir_y = directions[i][1];
            q.ray.dir_z = directions[i][2];
            q.ray.tnear = 0;
            q.ray.tfar = directions[i][3];
            q.ray.mask = ~0u;
            q.ray.flags = 0;
            q.ray.time = 0;
            q.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            q.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            if (anyHit) {
                rtcOccluded1(scene, &context, &q.ray);
                (*t)[i] = q.ray.tfar < 0 ? 0.0f : INFINITY; // tfar = -inf marks an occluded ray
            } else {
                rtcIntersect1(scene, &context, &q);
                (*t)[i] = q.hit.geomID != RTC_INVALID_GEOMETRY_ID ? q.ray.tfar : INFINITY;
            }
        }
    };
    // The CPUs this process may run on (affinity and cgroup cpusets), which
    // is what the OpenCL CPU devices use too.
    cpu_set_t allowed;
    unsigned threads = sched_getaffinity(0, sizeof allowed, &allowed) == 0 ? unsigned(CPU_COUNT(&allowed))
                                                                           : std::thread::hardware_concurrency();
    threads = std::max(1u, threads);
    auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (unsigned k = 0; k < threads; ++k) pool.emplace_back(work, n * k / threads, n * (k + 1) / threads);
    for (std::thread& th : pool) th.join();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace wv
