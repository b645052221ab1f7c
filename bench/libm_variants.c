// Whether glibc's CPU-selected variants of sincosf, sinf, cosf, expf and logf (x86-64: FMA or
// SSE2, chosen at load time by ifunc) give the same bits, over every float argument.
// docs/design.md, "The determinism contract", has the result for glibc 2.36.
//
//   gcc -O2 -ffp-contract=off -fno-builtin -o build/libm_variants bench/libm_variants.c -lm
//   build/libm_variants > fma.txt                  # the variants this CPU selects
//   GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4,-AVX512F build/libm_variants > sse2.txt
//   diff fma.txt sse2.txt   # a line per 1/64 of the bit patterns: chunk, then a hash per
//                           # function (sincosf, sinf, cosf, expf, logf)
//   build/libm_variants sincosf LO HI   # every argument in [LO, HI) (bit patterns) and its
//                                      # result bits, to find where two variants differ
//
// Takes about 6 minutes of one core per run (2^32 arguments, five functions).
#define _GNU_SOURCE
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t bits_of(float f) {
  uint32_t b;
  memcpy(&b, &f, sizeof b);
  return b;
}

static uint64_t mix(uint64_t h, float r) { return (h ^ bits_of(r)) * 0x100000001b3ull; }

static float from_bits(uint32_t b) {
  float x;
  memcpy(&x, &b, sizeof x);
  return x;
}

int main(int argc, char** argv) {
  if (argc == 4) {  // dump one function over [LO, HI)
    const int is_exp = strcmp(argv[1], "expf") == 0, is_log = strcmp(argv[1], "logf") == 0;
    const uint64_t lo = strtoull(argv[2], 0, 0), hi = strtoull(argv[3], 0, 0);
    for (uint64_t i = lo; i < hi; ++i) {
      const float x = from_bits((uint32_t)i);
      float s = 0, c = 0;
      if (is_exp) s = expf(x);
      else if (is_log) s = logf(x);
      else sincosf(x, &s, &c);
      printf("%08x %08x %08x\n", (uint32_t)i, bits_of(s), bits_of(c));
    }
    return 0;
  }
  for (uint32_t chunk = 0; chunk < 64; ++chunk) {
    uint64_t h[5];
    for (int k = 0; k < 5; ++k) h[k] = 0xcbf29ce484222325ull;
    for (uint64_t i = (uint64_t)chunk << 26; i < (uint64_t)(chunk + 1) << 26; ++i) {
      const float x = from_bits((uint32_t)i);
      float s, c;
      sincosf(x, &s, &c);
      h[0] = mix(mix(h[0], s), c);
      h[1] = mix(h[1], sinf(x));
      h[2] = mix(h[2], cosf(x));
      h[3] = mix(h[3], expf(x));
      h[4] = mix(h[4], logf(x));
    }
    printf("%2u %016llx %016llx %016llx %016llx %016llx\n", chunk, (unsigned long long)h[0],
           (unsigned long long)h[1], (unsigned long long)h[2], (unsigned long long)h[3],
           (unsigned long long)h[4]);
    fflush(stdout);
  }
  return 0;
}
