/* SIMD across work-items on PoCL's CPU devices.
 *
 * PoCL runs a work-group as a loop over its work-items. Where the host set
 * LLVM's options for it (host/cl/PoclVectorizer.h: SLP off, the loop
 * vectorizer's width forced to 16), LLVM runs 16 work-items per instruction
 * in every work-item loop it can legally vectorize: one without vector
 * types, atomics, prefetches, switches or loops of unknown trip count (LLVM
 * makes a switch of a chain of equality tests on one value: lights/lights.h,
 * light_is). generate, generate_light and shade_eyelight run so as written
 * wherever the options are in force. The shade kernels tell the code they
 * share whether they do (a constant: shade_slot leaves out its prefetch
 * hints, queue pushes go through the group rather than by an atomic per item,
 * core/queues.h): SIMD_CAMERA_SHADING and SIMD_LIGHT_SHADING are 1 where the
 * host set the options and chose SIMD for the camera paths' shade kernel,
 * shade or shade_bidirectional, or for shade_light (Renderer::deviceOptions
 * says when). */
#ifndef WAVEVCM_SIMD_H
#define WAVEVCM_SIMD_H

#ifndef SIMD_CAMERA_SHADING
#define SIMD_CAMERA_SHADING 0
#endif
#ifndef SIMD_LIGHT_SHADING
#define SIMD_LIGHT_SHADING 0
#endif

/* SCALAR_LOOP, before a loop inside a work-item that must stay a loop, where
 * the options are in force (the host then passes LLVM_OPTIONS_KEY to every
 * render program): the forced width also reaches the short loops inside a
 * work-item (a hash grid's eight buckets, a bucket's one or two candidates),
 * which would then run their few iterations as a scalar remainder behind the
 * vector loop's checks (merge lost 6-10 %). Without the options the hint is
 * left out: it cost merge 10 % there (caustics scene, bpm), LLVM treating
 * those loops better unhinted. */
#ifdef LLVM_OPTIONS_KEY
#define SCALAR_LOOP _Pragma("clang loop vectorize(disable)")
#else
#define SCALAR_LOOP
#endif

#endif
