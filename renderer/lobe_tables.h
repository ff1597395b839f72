#pragma once
// Tabulated Disney lobes for BSDF sampling with point sets: the renderer's
// side of "the backend knows what is being sampled" (renderer/README.md,
// "Sampling contexts").
//
// A point set for a lobe follows one fixed target: the lobe of one material
// at one view direction wo, tabulated on the equal-area sphere map
// (materials/disney_target.h). A shading point's wo is continuous, so the
// tables are binned: for every Disney material of a scene, `thetaBins`
// tables over theta_o in [0, 90) degrees, each at its bin's centre, and for an
// anisotropic material also `phiBins` bins over phi_o folded into [0, 90]
// degrees. A shading point samples the table of its bin:
//  - isotropic: the table is made at phi_o = 0 and rotated about the normal
//    to the point's phi_o, which leaves f unchanged, so only theta_o is
//    approximated;
//  - anisotropic: f is symmetric under x -> -x and y -> -y (the GGX
//    ellipse's axes are the frame's), so wo is folded into the first
//    quadrant, the direction drawn there, and the folds undone.
// Which density a table holds depends on the estimator (renderer/README.md,
// "Sampling contexts"): f cos for BSDF sampling alone, the density that is
// exact for a constant light; under MIS with light sampling the material's
// own sampling pdf, which gives a sharp lobe (a clear coat) the share of
// samples light sampling cannot, where f cos gives it its small albedo share.
// Any table is a valid importance density (positive wherever the lobe is,
// f > 0 on the whole upper hemisphere), so sampling the bin's table instead of
// the exact lobe at wo costs variance, never bias, provided the estimator
// divides by the pdf of the table actually used (pdf() below).

#include <memory>
#include <optional>
#include <vector>

#include "materials/bsdf.h"
#include "materials/disney.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

struct LobeTableSettings {
  int thetaBins = 9;   // over theta_o in [0, 90) degrees
  int phiBins = 3;     // over folded phi_o in [0, 90] degrees; anisotropic materials only
  int phiCells = 256;  // table resolution (rows = phiCells / 2), as the `disney` target's
  // The tables' density: 0 f cos, 1 the material's own sampling pdf
  // (`mix` of materials/disney_target.h); nullopt: chosen by the estimator
  // (lobeTablesFor in renderer/render.h).
  std::optional<double> samplingMix;
};

// One shading point's table and the map from the table's frame to the
// shading frame.
struct LobeFrame {
  const GridTarget *table = nullptr;
  double cosPhi = 1, sinPhi = 0;  // isotropic: rotation by phi_o
  double flipX = 1, flipY = 1;    // anisotropic: the folds

  // The direction (shading frame) that the table's point x stands for.
  Vec3 direction(Point2 x) const;
  // The density per unit solid angle with which direction(x) is drawn when x
  // follows the table; 0 below the surface.
  double pdf(Vec3 wi) const;
};

class LobeTables {
 public:
  // Tables for every distinct DisneyBrdf among `materials`; other materials
  // get none. Throws std::invalid_argument for bins < 1, a mix outside
  // [0, 1] or none given.
  LobeTables(const std::vector<std::shared_ptr<const Bsdf>> &materials,
             const LobeTableSettings &settings = {});

  // The frame for `material` at wo (shading frame, wo.z > 0); nullopt for a
  // material without tables.
  std::optional<LobeFrame> frame(const Bsdf *material, Vec3 wo) const;

  // Every table, material by material and bin by bin.
  std::vector<const Target *> targets() const;
  std::size_t materials() const { return entries_.size(); }
  const LobeTableSettings &settings() const { return settings_; }

 private:
  struct Entry {
    const DisneyBrdf *material;
    bool anisotropic;
    std::vector<std::unique_ptr<GridTarget>> tables;  // theta-major, then phi
  };
  LobeTableSettings settings_;
  std::vector<Entry> entries_;
};

}  // namespace nuld
