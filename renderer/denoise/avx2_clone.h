// The denoiser's hottest loops (patch distances, regression fits) also compiled for AVX2 and
// chosen at load time where the CPU has it (the build targets plain x86-64): 4 doubles or 8 floats
// a step instead of 2 or 4, 10 % of the denoiser's time on a 1280x720 frame. No FMA (GCC's avx2
// target does not enable it, and the build sets -ffp-contract=off): each add, multiply, divide and
// square root is the same IEEE result either way, so a machine gives the same bits with or without
// the clones (expf is glibc's, which picks its own variant per CPU, as before). clang does not
// clone function templates: there the loops stay plain.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define KILN_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define KILN_AVX2_CLONE
#endif
