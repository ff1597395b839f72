/* The interface of a nuld sampler plugin, version 1, kept as it was for the
 * plugins built against it: nuld still loads them (plugins/README.md says
 * how their pairs map onto today's domains). New plugins use version 2,
 * plugins/nuld_sampler.h, which tells a sampler what each number is for.
 * C99 and this file alone:
 *
 *   cc -O2 -shared -fPIC my_sampler.c -o libmy_sampler.so
 *   nuld render default --backend plugin:./libmy_sampler.so[:ARGS]
 *
 * A render asks for N = spp points of every pixel and dimension pair, each
 * in [0, 1)^2. Pair 0 places the sample in the pixel; bounce d (from 0) uses
 * pair 1 + 3d for the light sample, 2 + 3d for the BSDF sample and 3 + 3d
 * (x only) for Russian roulette. Sample i of a pixel takes point i of every
 * pair, so the plugin decides how pairs are matched: sets randomized
 * independently per pair are safe, the same points in the same order for
 * two pairs correlate them (nuld's set samplers shuffle each set).
 * nuld maps the points as it maps its classic samplers' (the light's and the
 * material's inverse CDFs) and refuses a point outside [0, 1)^2 or a NaN. */
#ifndef NULD_SAMPLER_H
#define NULD_SAMPLER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised whenever the structs or the functions' meaning change; nuld refuses
 * a plugin built for another version. */
#define NULD_SAMPLER_VERSION 1

typedef struct nuld_sampler_setup {
  /* What the render asks for. */
  uint64_t seed;          /* the render's seed (repeats of a study differ) */
  uint32_t spp;           /* samples per pixel: the points of a pixel's pair */
  uint32_t width, height; /* pixel (x, y), y = 0 the top row, x < width */
  uint32_t pairs;         /* the pairs a path may ask: 0 .. pairs - 1 */
  const char *arguments;  /* ARGS of plugin:PATH:ARGS, "" without */
  /* What the plugin answers. nuld sets pairs_served to `pairs`: lower it to
   * serve pairs 0 .. pairs_served - 1 only, the rest taking nuld's sobol. */
  uint32_t pairs_served;
  char error[256]; /* when create returns NULL: why, in words */
} nuld_sampler_setup;

typedef struct nuld_sampler {
  /* The sampler of one render, or NULL (setup->error says why). */
  void *(*create)(nuld_sampler_setup *setup);
  /* Points first .. first + count - 1 of pixel (x, y)'s set for `pair`,
   * written as count (x, y) pairs into xy[0 .. 2 count). Called from many
   * threads at once, and a pure function of its arguments and the state:
   * nuld's renders are the same for any thread count. Returns 0, or a
   * nonzero code that fails the render. */
  int (*fill)(const void *state, uint32_t x, uint32_t y, uint32_t pair, uint32_t first,
              uint32_t count, double *xy);
  void (*destroy)(void *state);
} nuld_sampler;

/* The one symbol a plugin exports: writes NULD_SAMPLER_VERSION to *version
 * and returns the plugin's functions. Exported also from a library built
 * with -fvisibility=hidden. */
#if defined(__GNUC__)
__attribute__((visibility("default")))
#endif
const nuld_sampler *
nuld_sampler_entry(int *version);

#ifdef __cplusplus
}
#endif

#endif /* NULD_SAMPLER_H */
