/* Prefetch hints: bring a structure's cache lines in before it is used, so
 * that a dependent load (a light path's next vertex, a hash-grid bucket)
 * does not stall the work-item on a cache miss. CPU devices only (PoCL
 * compiles for the host's x86 target, where clang's builtin becomes a
 * prefetch instruction); elsewhere the hint is nothing, and a streaming store
 * a plain one. A prefetch keeps LLVM's loop vectorizer off the work-item loop
 * it is in: the shade kernels leave them out where PoCL runs them in SIMD
 * (core/simd.h), and -DNO_PREFETCH builds without any, for experiments. */
#ifndef WAVEVCM_PREFETCH_H
#define WAVEVCM_PREFETCH_H

#if (defined(__x86_64__) || defined(__i386__)) && !defined(NO_PREFETCH)
#define HAS_PREFETCH 1
/* The first and the last cache line of [p, p + bytes): all of it for what
 * spans at most two 64-byte lines (a 128-byte LightVertex or a triangle's
 * 48 bytes of vertices at 16-byte alignment). An element of at most 16
 * bytes, aligned to its size, lies in one line: one hint. (With a second
 * hint to the same line, 36 % of `pt`'s `shade` samples on the AMD EPYC
 * machine sat on prefetch_hit_state's last hint, as if waiting for a free
 * miss slot; with one, `pt` ran 1.08-1.19× faster there.) */
#define PREFETCH(p, bytes)                                                                                 \
    do {                                                                                                   \
        __builtin_prefetch((__global const char*)(p));                                                     \
        if ((bytes) > 16)                                                                                  \
            __builtin_prefetch((__global const char*)(p) + (bytes) - 1);                                   \
    } while (0)
/* A store that bypasses the caches (x86 MOVNT), for records scattered over
 * an array larger than the caches: a whole cache line written this way is
 * not read from memory first. Such stores are weakly ordered; the kernels
 * that read them run in a later command, after PoCL's completion of this one,
 * whose locked instructions order them. -DNO_PREFETCH makes them plain. */
#define STREAM_STORE(value, p) __builtin_nontemporal_store((value), (p))
#else
#define PREFETCH(p, bytes) ((void)0)
#define STREAM_STORE(value, p) (*(p) = (value))
#endif

#endif
