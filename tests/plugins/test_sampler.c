/* A sampler plugin that misbehaves on request, for the plugin tests
 * (tests/backends/plugin_backend_test.cpp, tests/tools/plugin_test.sh).
 * ARGS: "" independent points; "nan", "one", "negative": that value at
 * sample 1 of pair 1 of every pixel; "fail": fill returns 7; "refuse":
 * create refuses; "camera": serves pair 0 only; "half": fill writes only
 * the first half of its points and returns 0; "impure": every call's points
 * differ (a shared counter, as a thread-unsafe sampler's state would);
 * "crash": fill dereferences NULL for pair 1; "stall": the first fill of
 * pair 1 sleeps 3 s. Built also without its entry
 * (NULD_TEST_NO_ENTRY) and for another version (NULD_TEST_VERSION). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "plugins/v1/nuld_sampler.h"

typedef struct {
  uint64_t seed;
  uint32_t width;
  char mode[16];
} state;

static uint64_t mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

static void *create(nuld_sampler_setup *setup) {
  if (strcmp(setup->arguments, "refuse") == 0) {
    snprintf(setup->error, sizeof setup->error, "refuses on purpose");
    return NULL;
  }
  state *s = calloc(1, sizeof *s);
  s->seed = mix(setup->seed), s->width = setup->width;
  snprintf(s->mode, sizeof s->mode, "%s", setup->arguments);
  if (strcmp(s->mode, "camera") == 0) setup->pairs_served = 1;
  return s;
}

static int fill(const void *p, uint32_t x, uint32_t y, uint32_t pair, uint32_t first,
                uint32_t count, double *xy) {
  const state *s = p;
  if (strcmp(s->mode, "fail") == 0) return 7;
  if (strcmp(s->mode, "crash") == 0 && pair == 1) {
    volatile double *nowhere = NULL;
    *nowhere = 1;
  }
  static int stalled = 0;
  if (strcmp(s->mode, "stall") == 0 && pair == 1 &&
      !__atomic_exchange_n(&stalled, 1, __ATOMIC_SEQ_CST))
    sleep(3);
  static uint64_t calls = 0;
  const uint64_t salt =
      strcmp(s->mode, "impure") == 0 ? __atomic_fetch_add(&calls, 1, __ATOMIC_RELAXED) : 0;
  const uint64_t set = mix(mix(s->seed + (uint64_t)y * s->width + x) + pair + salt);
  const uint32_t written = strcmp(s->mode, "half") == 0 && count > 1 ? count / 2 : count;
  for (uint32_t i = 0; i < written; ++i) {
    const uint64_t h = mix(set + first + i);
    xy[2 * i] = (double)(h >> 11) * 0x1.0p-53, xy[2 * i + 1] = (double)(mix(h) >> 11) * 0x1.0p-53;
  }
  if (pair == 1 && count > 1 && first == 0) {
    if (strcmp(s->mode, "nan") == 0) xy[3] = NAN;
    if (strcmp(s->mode, "one") == 0) xy[2] = 1.0;
    if (strcmp(s->mode, "negative") == 0) xy[2] = -0.25;
  }
  return 0;
}

static void destroy(void *s) { free(s); }

#ifndef NULD_TEST_NO_ENTRY
const nuld_sampler *nuld_sampler_entry(int *version) {
  static const nuld_sampler functions = {create, fill, destroy};
#ifdef NULD_TEST_VERSION
  *version = NULD_TEST_VERSION;
#else
  *version = NULD_SAMPLER_VERSION;
#endif
  return &functions;
}
#else
const nuld_sampler *another_entry(int *version) {
  static const nuld_sampler functions = {create, fill, destroy};
  *version = NULD_SAMPLER_VERSION;
  return &functions;
}
#endif
