#pragma once
// The sample layout of a path: every number a path draws belongs to a named
// *domain* of one or two dimensions, so that a sampler can tell what it
// samples (pbrt-v4's Get1D/Get2D against a dimension counter, Mitsuba 3's
// next_1d/next_2d, OpenQMC's keyed domains). One table in
// docs/architecture.md ("The sample layout") is this file in words.
//
// Domain 0 places the sample in the pixel; bounce d (from 0) then draws, in
// this order, the light choice (1D: which light next-event estimation
// samples), the light sample (2D), the lobe choice (1D: which lobe of a
// layered material is sampled), the BSDF direction (2D) and Russian
// roulette (1D). Domains are numbered in that order, five a bounce; a
// backend keys its randomization by the number, and a full-dimensional
// sequence gives domain k the dimensions from firstDimension(k) on.

#include <cstdint>

#include "sampler/enum_names.h"

namespace nuld {

enum class SampleRole : std::uint8_t { Camera, LightChoice, Light, LobeChoice, Bsdf, Roulette };
// The roles' names as the docs, plugins and Python spell them.
inline constexpr auto kSampleRoleNames =
    enumTable<SampleRole>("sample role", {{"camera", SampleRole::Camera},
                                          {"light-choice", SampleRole::LightChoice},
                                          {"light", SampleRole::Light},
                                          {"lobe-choice", SampleRole::LobeChoice},
                                          {"bsdf", SampleRole::Bsdf},
                                          {"roulette", SampleRole::Roulette}});
constexpr const auto &enumNames(SampleRole) { return kSampleRoleNames; }

struct SampleDomain {
  SampleRole role = SampleRole::Camera;
  int bounce = 0;      // the camera's: 0, with the first bounce
  int dimensions = 2;  // 1 or 2
};

struct SampleLayout {
  static constexpr std::uint32_t kPerBounce = 5;
  static constexpr std::uint32_t kDimensionsPerBounce = 7;

  static constexpr std::uint32_t camera = 0;
  static constexpr std::uint32_t lightChoice(int bounce) {
    return 1 + kPerBounce * unsigned(bounce);
  }
  static constexpr std::uint32_t light(int bounce) { return lightChoice(bounce) + 1; }
  static constexpr std::uint32_t lobeChoice(int bounce) { return lightChoice(bounce) + 2; }
  static constexpr std::uint32_t bsdf(int bounce) { return lightChoice(bounce) + 3; }
  static constexpr std::uint32_t roulette(int bounce) { return lightChoice(bounce) + 4; }

  // The domains of a path of `bounces` bounces: 0 .. domains(bounces) - 1.
  static constexpr std::uint32_t domains(int bounces) { return 1 + kPerBounce * unsigned(bounces); }

  static constexpr SampleDomain domain(std::uint32_t index) {
    if (index == camera) return {};
    const int bounce = int((index - 1) / kPerBounce);
    constexpr SampleRole kRoles[kPerBounce] = {SampleRole::LightChoice, SampleRole::Light,
                                               SampleRole::LobeChoice, SampleRole::Bsdf,
                                               SampleRole::Roulette};
    const SampleRole role = kRoles[(index - 1) % kPerBounce];
    const bool twoD = role == SampleRole::Light || role == SampleRole::Bsdf;
    return {role, bounce, twoD ? 2 : 1};
  }
  static constexpr int dimensions(std::uint32_t index) { return domain(index).dimensions; }
  static constexpr int bounceOf(std::uint32_t index) { return domain(index).bounce; }

  // The domain's first dimension in one sequence of all a path's numbers:
  // the camera's 0 and 1, bounce d's seven from 2 + 7d in the order above.
  static constexpr std::uint32_t firstDimension(std::uint32_t index) {
    if (index == camera) return 0;
    constexpr std::uint32_t kOffset[kPerBounce] = {0, 1, 3, 4, 6};
    return 2 + kDimensionsPerBounce * ((index - 1) / kPerBounce) +
           kOffset[(index - 1) % kPerBounce];
  }
};

static_assert(SampleLayout::firstDimension(SampleLayout::roulette(0)) + 1 ==
              SampleLayout::firstDimension(SampleLayout::lightChoice(1)));
static_assert(SampleLayout::domain(SampleLayout::bsdf(2)).role == SampleRole::Bsdf &&
              SampleLayout::domain(SampleLayout::bsdf(2)).bounce == 2);

}  // namespace nuld
