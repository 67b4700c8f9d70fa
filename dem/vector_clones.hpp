#pragma once
// DEMCAL_VECTOR_CLONES: compile a hot loop for three instruction sets
// (AVX-512, AVX2, the x86-64 baseline); the loader picks the best the
// processor has, so one portable binary runs 8, 4 or 2 doubles per
// instruction. Not under the sanitizers (their run-time cannot intercept the
// ifunc resolver early enough) nor with compilers other than GCC. The engine
// is built without fused multiply-add (dem/CMakeLists.txt), so every version
// rounds as the baseline does.

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__)
#define DEMCAL_VECTOR_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define DEMCAL_VECTOR_CLONES
#endif
