/* The interface of a nuld sampler plugin, version 2: your own sampler as a
 * row of nuld's render studies (plugins/README.md). C99 and this file alone:
 *
 *   cc -O2 -shared -fPIC my_sampler.c -o libmy_sampler.so
 *   nuld render default --backend plugin:./libmy_sampler.so[:ARGS]
 *
 * A render asks for N = spp samples of every pixel and *domain* of a path
 * (docs/architecture.md, "The sample layout"): domain 0 places the sample in
 * the pixel (2D); bounce d (from 0) then has five, numbered 1 + 5d .. 5 + 5d:
 * the light choice (1D), the light sample (2D), the lobe choice (1D), the
 * BSDF direction (2D) and Russian roulette (1D). create is told the
 * integrator and the whole layout, fill the domain it fills, so a sampler
 * can treat a role as it likes (stratify the light with the camera, leave
 * roulette to nuld). Sample i of a pixel takes sample i of every domain, so
 * the plugin decides how domains are matched: sets randomized independently
 * per domain are safe, the same numbers in the same order for two domains
 * correlate them (nuld's set samplers shuffle each set). nuld maps the
 * samples as it maps its classic samplers' (the light's and the material's
 * inverse CDFs) and refuses a number outside [0, 1) or a NaN.
 *
 * Plugins built against version 1 (plugins/v1/nuld_sampler.h: 2D pairs
 * only) keep loading unchanged; plugins/README.md says how their pairs map
 * onto the domains. */
#ifndef NULD_SAMPLER_H
#define NULD_SAMPLER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised whenever the structs or the functions' meaning change; nuld loads
 * this version and version 1, and refuses any other. */
#define NULD_SAMPLER_VERSION 2

/* What a domain's numbers are for. */
typedef enum nuld_role {
  NULD_ROLE_CAMERA = 0,       /* 2D: the position in the pixel */
  NULD_ROLE_LIGHT_CHOICE = 1, /* 1D: which light next-event estimation samples */
  NULD_ROLE_LIGHT = 2,        /* 2D: the point on that light (or the map) */
  NULD_ROLE_LOBE_CHOICE = 3,  /* 1D: which lobe of a layered material */
  NULD_ROLE_BSDF = 4,         /* 2D: the direction within that lobe */
  NULD_ROLE_ROULETTE = 5      /* 1D: Russian roulette */
} nuld_role;

typedef struct nuld_domain {
  uint32_t index;           /* its number, 0 .. domains - 1 */
  uint32_t role;            /* a nuld_role */
  uint32_t bounce;          /* 0 for the camera and the first bounce */
  uint32_t dimensions;      /* 1 or 2 */
  uint32_t first_dimension; /* where it starts in one sequence of all of a
                               path's numbers (camera 0-1, bounce d 2 + 7d ..) */
  uint32_t served;          /* nuld sets 1; create may set 0 to leave the
                               domain to nuld's sobol */
} nuld_domain;

typedef struct nuld_sampler_setup {
  /* What the render asks for. */
  uint64_t seed;          /* the render's seed (repeats of a study differ) */
  uint32_t spp;           /* samples per pixel: the samples of a pixel's domain */
  uint32_t width, height; /* pixel (x, y), y = 0 the top row, x < width */
  const char *integrator; /* "path", "direct", "light" or "bsdf" */
  uint32_t domains;       /* the domains a path may ask: 0 .. domains - 1 */
  nuld_domain *layout;    /* domains entries, layout[k].index == k; create
                             may clear `served` of any */
  const char *arguments;  /* ARGS of plugin:PATH:ARGS, "" without */
  char error[256];        /* when create returns NULL: why, in words */
} nuld_sampler_setup;

typedef struct nuld_sampler {
  /* The sampler of one render, or NULL (setup->error says why). */
  void *(*create)(nuld_sampler_setup *setup);
  /* Samples first .. first + count - 1 of pixel (x, y)'s set for `domain`
   * (one of create's layout entries, served), written sample by sample as
   * count * domain->dimensions numbers into out. Called from many threads
   * at once, and a pure function of its arguments and the state: nuld's
   * renders are the same for any thread count. Returns 0, or a nonzero
   * code that fails the render. */
  int (*fill)(const void *state, uint32_t x, uint32_t y, const nuld_domain *domain, uint32_t first,
              uint32_t count, double *out);
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
