/* A nuld sampler plugin: independent uniform points, each coordinate a hash
 * of (seed, pixel, pair, sample). It renders as nuld's `independent` does,
 * with other random numbers (plugins/README.md). */
#include <stdio.h>
#include <stdlib.h>

#include "nuld_sampler.h"

static uint64_t mix(uint64_t z) { /* splitmix64's finalizer */
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
static double unit(uint64_t bits) { return (double)(bits >> 11) * 0x1.0p-53; } /* [0, 1) */

typedef struct {
  uint64_t key;
  uint32_t width;
} state;

static void *create(nuld_sampler_setup *setup) {
  if (setup->arguments[0]) {
    snprintf(setup->error, sizeof setup->error, "takes no arguments (got '%s')", setup->arguments);
    return NULL;
  }
  state *s = malloc(sizeof *s);
  if (s)
    *s = (state){mix(setup->seed + 0x9e3779b97f4a7c15ull), setup->width};
  else
    snprintf(setup->error, sizeof setup->error, "out of memory");
  return s;
}

static int fill(const void *p, uint32_t x, uint32_t y, uint32_t pair, uint32_t first,
                uint32_t count, double *xy) {
  const state *s = p;
  const uint64_t set = mix(mix(s->key + (uint64_t)y * s->width + x) + pair);
  for (uint32_t i = 0; i < count; ++i) {
    const uint64_t h = mix(set + first + i);
    xy[2 * i] = unit(h), xy[2 * i + 1] = unit(mix(h));
  }
  return 0;
}

static void destroy(void *s) { free(s); }

const nuld_sampler *nuld_sampler_entry(int *version) {
  static const nuld_sampler functions = {create, fill, destroy};
  *version = NULD_SAMPLER_VERSION;
  return &functions;
}
