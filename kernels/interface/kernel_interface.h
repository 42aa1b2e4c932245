/* The render kernels' interface, declared once for both compilers.
 *
 * Every render kernel takes the same parameters: the device buffers of
 * RENDER_BUFFERS, in that order, then the launch's scalars (LaunchParams, by
 * value). A kernel is written `__kernel void name(RENDER_KERNEL_PARAMS)` and
 * the host binds every kernel from the same lists (host/render/KernelBindings.h),
 * so no argument order is written anywhere else and a kernel needs no
 * plumbing to reach a buffer: it uses it by name. Helpers take the buffers as
 * one `const RenderBuffers*`.
 *
 * X(addressSpace, elementType, name, elementsPerPathSlot): the last column is
 * 0 for buffers not sized by the wavefront; the path state (one element per
 * path slot, structure of arrays) is allocated from it. */
#ifndef WAVEVCM_KERNEL_INTERFACE_H
#define WAVEVCM_KERNEL_INTERFACE_H

#include "queue_ids.h"
#include "shared_types.h"

#ifndef __OPENCL_C_VERSION__
namespace wv {
#endif

/* The scene, uploaded once per render (host/render/SceneBuffers.h). */
#define SCENE_BUFFERS(X)                                                                                   \
    X(__global, BvhNode, nodes, 0)           /* the flattened BVH */                                       \
    X(__global, TrianglePacket, trianglePackets, 0) /* the BVH leaves' triangles */                        \
    X(__global, float4, triVertices, 0)      /* 3 per triangle, BVH order */                               \
    X(__global, float4, triNormals, 0)       /* 3 per triangle with vertex normals, else 1 */              \
    X(__global, int, triMaterials, 0)        /* material index per triangle */                             \
    X(__global, Material, materials, 0)                                                                    \
    X(__global, Light, lights, 0)            /* the light table (at least one entry) */                    \
    X(__global, float, lightCdf, 0)          /* light selection by power, lights + 1 entries */            \
    X(__global, int, triangleLight, 0)       /* light index of an emissive triangle, else -1 */            \
    X(__global, float4, textureTexels, 0)    /* every texture's texels (materials/texture.h) */            \
    X(__global, TextureInfo, textures, 0)    /* where each texture's texels start */                       \
    X(__global, float2, triUVs, 0)           /* TEXCOORD_0 per triangle corner, with textures, else 1 */   \
    X(__global, float2, triUVs1, 0)          /* TEXCOORD_1 per triangle corner if a texture reads it, else 1 */ \
    X(__global, float4, triColors, 0)        /* COLOR_0 per triangle corner with vertex colours, else 1 */ \
    X(__global, float4, triTangents, 0)      /* tangent, handedness per corner, with normal maps, else 1 */ \
    X(__global, float4, envRadiance, 0)      /* environment map texels (lights/environment.h), else 1 */   \
    X(__global, float, envMarginalCdf, 0)    /* over its rows, height + 1 entries */                       \
    X(__global, float, envConditionalCdf, 0) /* over each row's texels, height × (width + 1) */            \
    X(__constant, SceneInfo, scene, 0)                                                                     \
    X(__constant, Camera, camera, 0)

/* One wavefront of paths, indexed by path slot (transport/path_state.h): two
 * regions of `capacity` slots, one per round parity. */
#define PATH_STATE_BUFFERS(X)                                                                              \
    X(__global, float4, rayOrigins, 1)                                                                     \
    X(__global, float4, rayDirections, 1)    /* w = tMax */                                                \
    X(__global, int, pathPixel, 1)           /* the sample: of a camera path (sample_pixel), index of a light path */ \
    X(__global, int, pathDepth, 1)           /* segments traced before the current ray (path_state.h) */   \
    X(__global, float4, pathThroughput, 1)                                                                 \
    X(__global, float, pathPrevPdf, 1)       /* pt: solid-angle pdf of the last BSDF sample, 0 = delta */  \
    X(__global, float4, pathMis, 1)          /* dVCM, dVC, dVM (mis.h) */                                  \
    X(__global, int, pathFlags, 1)           /* PATH_* bits */                                             \
    X(__global, int, pathLastVertex, 1)      /* a light path's last stored vertex */                      \
    X(__global, float, hitT, 1)                                                                            \
    X(__global, int, hitTriangle, 1)                                                                       \
    X(__global, float2, hitBary, 1)                                                                        \
    X(__global, int, queryBuckets, 8)        /* vcm: the hit's merge query (transport/merge_query.h) */   \
    X(__global, float4, shadowOrigins, 1)                                                                  \
    X(__global, float4, shadowDirections, 1) /* w = tMax */                                                \
    X(__global, float4, shadowContribution, 1)                                                             \
    X(__global, int, shadowPixel, 1)         /* where a light-tracing shadow ray splats */

/* The work queues (queue_ids.h): path slots, and their counters. */
#define QUEUE_BUFFERS(X)                                                                                   \
    X(__global, int, queueItems, QUEUE_COUNT) /* queue q: [q·capacity, (q+1)·capacity) */                  \
    X(__global, int, queueCounters, 0)       /* COUNTER_COUNT counters, COUNTER_STRIDE apart */

/* Per pixel: this iteration's sample by technique family, and the running means. */
#define IMAGE_BUFFERS(X)                                                                                   \
    X(__global, float4, pixelRadiance, 0)      /* unidirectional: emission hits, NEE, background; per \
                                                  camera sample (samplesPerIteration per pixel) */         \
    X(__global, float4, connectionRadiance, 0) /* vertex connection, camera side; per camera sample */    \
    X(__global, float4, mergingRadiance, 0)    /* vertex merging; per camera sample */                     \
    X(__global, float4, splatRadiance, 0)      /* light tracing's splats (float compare-and-swap adds) */  \
    X(__global, float4, framebuffer, 0)        /* running mean */                                          \
    X(__global, float4, familyMeans, 0)        /* 3 per pixel: running means by family (--aov techniques) */

/* The light sub-paths of a batch, for connection and merging. */
#define LIGHT_PATH_BUFFERS(X)                                                                              \
    X(__global, LightVertex, lightVertices, 0) /* ppm, bpm: MergeVertex (StoredLightVertex) */           \
    X(__global, int, lightPathHead, 0)       /* last stored vertex per light path of the batch */          \
    X(__global, int, bucketStarts, 0)        /* hash grid (hash_grid.h): first entry per bucket, +1 */     \
    X(__global, MergeVertex, bucketVertices, 0) /* hash grid: the vertices as merging reads them, bucket order */ \
    X(__global, float4, connectionOrigins, 0)      /* the connection queue (connect_vertices.cl): rays */ \
    X(__global, float4, connectionDirections, 0)   /* w = tMax */                                         \
    X(__global, float4, connectionContribution, 0) /* w: the camera sample, an int (connection_sample) */

#define RENDER_BUFFERS(X) \
    SCENE_BUFFERS(X) PATH_STATE_BUFFERS(X) QUEUE_BUFFERS(X) IMAGE_BUFFERS(X) LIGHT_PATH_BUFFERS(X)

/* The scalars of one launch, set by the queue manager before every launch.
 * 4-byte scalars only: identical layout in both compilers, and rusticl
 * (Mesa 22.3) miscompiles by-value structs with array members. */
typedef struct LaunchParams {
    /* The round (host/render/Renderer.cpp: round) */
    int capacity;       /* path slots */
    int rayQueue;       /* RAYS(parity): generate appends to it, extend consumes it */
    int nextRayQueue;   /* RAYS(1 - parity): paths that continue */
    /* The phase */
    int firstSample;     /* its samples are [firstSample, firstSample + samples) */
    int samples;
    int cameraPaths;     /* 1: camera sub-paths, 0: light sub-paths */
    int firstSplatPath;  /* light paths from this index on splat onto the image (lt, bpt, vcm; ppm
                          * and bpm have no splats); the others did in an earlier pass */
    /* The iteration and light-path batch */
    uint iteration;       /* the global index of this iteration (random numbers, merge radius) */
    int accumulated;      /* samples per pixel already in this renderer's running means */
    int firstLightPath;   /* light path index of the batch's first path */
    int vertexCapacity;   /* lightVertices' length */
    int connectionCapacity; /* the connection queue's length (0 without one) */
    float vmWeightFactor; /* Georgiev's report, eq. 20: η_VCM = π r² N_light, 0 without merging */
    float vcWeightFactor; /* 1/η_VCM with connection and merging, else 0 */
    float mergeRadius;
    float vmNormalization; /* 1/(π r² N_light) */
    uint cellCount;        /* hash grid buckets */
    /* The render */
    uint seed;
    int maxPathLength;     /* segments of a full path (path_state.h) */
    float lightTracePaths; /* light paths per pass of an iteration (the pixels), for light tracing's MIS */
    int pixels;
    int samplesPerIteration; /* samples (and light paths) per pixel in one iteration: path_state.h */
    int techniques;    /* accumulate: running means per technique family too */
} LaunchParams;

/* One number from the sizes of the structs the host and the kernels share
 * and the number of render buffers, computed alike by both compilers.
 * Renderer::programOptions passes the host's as HOST_STRUCT_LAYOUT, so that
 * kernel sources declaring these otherwise than the wavevcm binary was built
 * with (edited or updated without rebuilding it; the kernels are read from
 * the source tree at run time) fail to build, with this check named in the
 * build log, instead of reading their arguments and buffers wrongly. */
#define RENDER_BUFFER_COUNT_ONE(space, type, name, perSlot) +1u
#define STRUCT_LAYOUT                                                                                        \
    ((uint)sizeof(LaunchParams) + 3u * (uint)sizeof(BvhNode) + 5u * (uint)sizeof(TrianglePacket4) +              \
     7u * (uint)sizeof(Camera) + 11u * (uint)sizeof(Material) + 13u * (uint)sizeof(TextureInfo) +                 \
     17u * (uint)sizeof(Light) + 19u * (uint)sizeof(SurfaceRecord) + 23u * (uint)sizeof(LightVertex) +            \
     29u * (uint)sizeof(MergeVertex) + 31u * (uint)sizeof(SceneInfo) + 41u * (uint)sizeof(TrianglePacket8) +      \
     37u * (0u RENDER_BUFFERS(RENDER_BUFFER_COUNT_ONE)))
#if defined(__OPENCL_C_VERSION__) && defined(HOST_STRUCT_LAYOUT)
typedef char kernel_sources_declare_shared_structs_otherwise_than_the_wavevcm_binary_rebuild_it
    [STRUCT_LAYOUT == HOST_STRUCT_LAYOUT ? 1 : -1];
#endif

#ifndef __OPENCL_C_VERSION__
} /* namespace wv */
#endif

#ifdef __OPENCL_C_VERSION__
#define RENDER_KERNEL_PARAM(space, type, name, perSlot) space type* name,
#define RENDER_KERNEL_PARAMS RENDER_BUFFERS(RENDER_KERNEL_PARAM) const LaunchParams params

/* The same buffers as one value, for helpers (after inlining, just the parameters). */
typedef struct RenderBuffers {
#define RENDER_BUFFER_MEMBER(space, type, name, perSlot) space type* name;
    RENDER_BUFFERS(RENDER_BUFFER_MEMBER)
#undef RENDER_BUFFER_MEMBER
} RenderBuffers;

#define RENDER_BUFFER_NAME(space, type, name, perSlot) name,
/* In a kernel: `RenderBuffers b = RENDER_BUFFERS_VALUE;` */
#define RENDER_BUFFERS_VALUE {RENDER_BUFFERS(RENDER_BUFFER_NAME)}
#endif

#endif
