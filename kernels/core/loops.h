/* SCALAR_LOOP, before a loop inside a work-item that must stay a loop.
 *
 * Where the host turns on PoCL's vectorization of work-items (host/cl/
 * PoclVectorizer.h: LLVM's vector width forced to the device's SIMD width),
 * the force also reaches every other loop LLVM can legally vectorize,
 * including the short ones inside a work-item: a hash grid's eight buckets,
 * a bucket's one or two candidates. Vectorized 16 wide, those run their few
 * iterations as a scalar remainder behind the vector loop's checks, and
 * `merge` lost 6-10 %. Elsewhere the hint changes nothing: such loops are
 * not vectorized anyway. */
#ifndef WAVEVCM_LOOPS_H
#define WAVEVCM_LOOPS_H

#define SCALAR_LOOP _Pragma("clang loop vectorize(disable)")

#endif
