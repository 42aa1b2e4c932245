/* Every kernel helper is INLINE. Static, so that a compiler that keeps a
 * helper out of line still has its definition (a plain C99 `inline` has
 * none: clang to PTX failed with unresolved externs); always_inline, because
 * the kernels are written to be inlined whole: a helper LLVM keeps out of
 * line cost connect_vertices 30 % on PoCL, and one with barriers crashes
 * PoCL 3.1's work-group pass. */
#ifndef WAVEVCM_INLINE_H
#define WAVEVCM_INLINE_H

#define INLINE static inline __attribute__((always_inline))

#endif
