/* A version-2 nuld sampler plugin: Latin hypercube (N-rooks) sets, each
 * dimension of a domain stratified into N = spp strata and the strata of
 * every dimension dealt in an order of their own, so that domains and
 * dimensions are matched at random. It reads the layout: ARGS is a list of
 * the roles it serves, "camera,light" (plugins/README.md names them),
 * every role without ARGS; the others it leaves to nuld's sobol. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nuld_sampler.h"

static uint64_t mix(uint64_t z) { /* splitmix64's finalizer */
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
static double unit(uint64_t bits) { return (double)(bits >> 11) * 0x1.0p-53; } /* [0, 1) */
static uint32_t gcd(uint32_t a, uint32_t b) { return b ? gcd(b, a % b) : a; }

static const char *const role_names[] = {"camera",      "light-choice", "light",
                                         "lobe-choice", "bsdf",         "roulette"};

typedef struct {
  uint64_t key;
  uint32_t width, spp;
} state;

/* Whether `role`'s name is in the comma-separated list. */
static int listed(const char *list, uint32_t role) {
  const size_t n = strlen(role_names[role]);
  for (const char *p = list; *p;) {
    const char *end = strchr(p, ',');
    const size_t len = end ? (size_t)(end - p) : strlen(p);
    if (len == n && strncmp(p, role_names[role], n) == 0) return 1;
    p += len + (end != NULL);
  }
  return 0;
}

static void *create(nuld_sampler_setup *setup) {
  const char *list = setup->arguments;
  /* Every name must be a role: a typo would silently serve nothing. */
  for (const char *p = list; *p;) {
    const char *end = strchr(p, ',');
    const size_t len = end ? (size_t)(end - p) : strlen(p);
    int known = 0;
    for (uint32_t r = 0; r < 6; ++r)
      known |= len == strlen(role_names[r]) && strncmp(p, role_names[r], len) == 0;
    if (!known) {
      snprintf(setup->error, sizeof setup->error,
               "ARGS: '%.*s' is not a role (expected camera, light-choice, light, lobe-choice, "
               "bsdf or roulette, comma-separated)",
               (int)len, p);
      return NULL;
    }
    p += len + (end != NULL);
  }
  if (*list)
    for (uint32_t k = 0; k < setup->domains; ++k)
      setup->layout[k].served = (uint32_t)listed(list, setup->layout[k].role);
  state *s = malloc(sizeof *s);
  if (s)
    *s = (state){mix(setup->seed + 0x9e3779b97f4a7c15ull), setup->width, setup->spp};
  else
    snprintf(setup->error, sizeof setup->error, "out of memory");
  return s;
}

/* Sample i's stratum in one dimension: i -> (a i + b) mod N, a coprime
 * with N, is a permutation of the strata drawn from `key`. */
static double coordinate(uint64_t key, uint32_t n, uint32_t i) {
  uint32_t a = (uint32_t)(mix(key) % n) | 1u;
  while (gcd(a, n) != 1) a += 1;
  const uint32_t b = (uint32_t)(mix(key + 1) % n);
  const uint32_t stratum = (uint32_t)(((uint64_t)a * i + b) % n);
  return (stratum + unit(mix(key + 2 + i))) / n;
}

static int fill(const void *p, uint32_t x, uint32_t y, const nuld_domain *domain, uint32_t first,
                uint32_t count, double *out) {
  const state *s = p;
  const uint64_t set = mix(mix(s->key + (uint64_t)y * s->width + x) + domain->index);
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t d = 0; d < domain->dimensions; ++d) {
      const double v = coordinate(mix(set + d), s->spp, first + i);
      out[i * domain->dimensions + d] = v < 1 ? v : 0x1.fffffffffffffp-1;
    }
  return 0;
}

static void destroy(void *s) { free(s); }

const nuld_sampler *nuld_sampler_entry(int *version) {
  static const nuld_sampler functions = {create, fill, destroy};
  *version = NULD_SAMPLER_VERSION;
  return &functions;
}
