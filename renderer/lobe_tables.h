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
// divides by the pdf of the route actually used (LobeFrame::pdf).
//
// A table is not always the better route (renderer/README.md, "Lobe
// routes"): a lobe narrower than the bin's sweep of its mirror direction
// (a glossy metal) is mostly missed by the table of the bin's centre. So
//  - each bin's route is measured when the tables are built: of the
//    material's own sampler and the table, the one whose estimates of
//    smooth lights vary least serves the bin; bins that keep the material's
//    sampler are no context for any backend;
//  - a tabulated sample can be a defensive mixture with the material's
//    sampler (off by default), which bounds its weight f cos / p by
//    1 / defensive times the material's;
//  - tables serve the first bounce only by default (`bounces`).

#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "materials/bsdf.h"
#include "materials/disney.h"
#include "materials/disney_target.h"
#include "materials/sampling.h"
#include "sampler/enum_names.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

// Which bins sample which table (renderer/README.md, "Lobe routes").
enum class LobeRouting {
  Measured,  // each bin its measured better of the material's sampler and its table
  Table,     // every bin its table (for comparisons)
};
inline constexpr auto kLobeRoutingNames = enumTable<LobeRouting>(
    "lobe routing", {{"measured", LobeRouting::Measured}, {"table", LobeRouting::Table}});
constexpr const auto &enumNames(LobeRouting) { return kLobeRoutingNames; }

struct LobeTableSettings {
  int thetaBins = 9;  // over theta_o in [0, 90) degrees
  int phiBins = 3;    // over folded phi_o in [0, 90] degrees; anisotropic materials only
  // Table resolution (rows = phiCells / 2). The tables that serve are the
  // broad lobes' (measured routes), which 64 x 32 cells hold about as well
  // as finer ones, and small tables stay in cache (renderer/README.md,
  // "Lobe routes", has the measurements).
  int phiCells = 64;
  // The tables' density: 0 f cos, 1 the material's own sampling pdf
  // (`mix` of materials/disney_target.h); nullopt: chosen by the estimator
  // (LobeTablesConfig::samplingMix).
  std::optional<double> samplingMix;
  LobeRouting routing = LobeRouting::Measured;
  // The defensive share d: a tabulated sample is drawn by the material's own
  // sample() with probability d (sampleRoute), and every estimator
  // divides by the mixture (1 - d) table + d material, so a table's weight
  // f cos / p is at most 1 / d times the material's own at that direction.
  // Off by default: the measured routes already keep the material's sampler
  // wherever a table misses its lobe, and the strip of the square that the
  // split hands to the material breaks the set's stratification (the
  // figures: renderer/README.md, "Lobe routes").
  double defensive = 0;
  // How many bounces, from the first, sample the tables (0: every bounce).
  // Beyond the first, a pixel's samples scatter over materials and bins, so
  // a table serves one or two of a pixel's points there: no gain measured,
  // for the lookups' time (renderer/README.md, "Lobe routes").
  int bounces = 1;
  friend bool operator==(const LobeTableSettings &, const LobeTableSettings &) = default;
};

// The lobe tables of one render: the user's settings and what the renderer
// derives from them for the render's integrator (lobeTablesFor in
// renderer/render.h, the one place that derives them). No option sets the
// derived fields.
struct LobeTablesConfig {
  LobeTableSettings settings;  // as the user set them
  // Derived: settings.samplingMix, else the estimator's choice (f cos for
  // BSDF sampling alone, the material's pdf under MIS).
  double samplingMix = 0;
  // Derived: whether a BSDF sample's whole contribution is weighed against
  // light samples by MIS, as in the direct integrator. The routes are then
  // measured under MIS, since a route that is best alone need not be best
  // once light sampling covers the lobe's broad parts. In path tracing a
  // BSDF sample also carries the indirect light at full weight, and routes
  // measured by BSDF sampling alone render better there (renderer/README.md,
  // "Lobe routes").
  bool underMis = false;

  LobeTablesConfig() = default;
  // Settings that give their mix, routes measured with or without MIS (for
  // tests and benchmarks that build tables directly). Throws
  // std::invalid_argument when the mix is not given.
  LobeTablesConfig(const LobeTableSettings &settings, bool underMis = false);
  friend bool operator==(const LobeTablesConfig &, const LobeTablesConfig &) = default;
};

// The layout of the renderer's lobe tables under `config` (cells and mix;
// the material and the view left at their defaults): the spec a model must
// match to serve them.
DisneyTargetSpec lobeTableLayout(const LobeTablesConfig &config);

// One shading point's table and the map from the table's frame to the
// shading frame.
struct LobeFrame {
  const GridTarget *table = nullptr;
  double cosPhi = 1, sinPhi = 0;  // isotropic: rotation by phi_o
  double flipX = 1, flipY = 1;    // anisotropic: the folds
  double defensive = 0;           // LobeTableSettings::defensive

  // The direction (shading frame) that the table's point x stands for.
  Vec3 direction(Point2 x) const;
  // The density per unit solid angle with which direction(x) is drawn when x
  // follows the table; 0 below the surface.
  double tablePdf(Vec3 wi) const;
  // The route's density per unit solid angle at wi: the defensive mixture
  // of the table's and the material's (`materialPdf`, the material's pdf at
  // wi); without a table, the material's sampler is the route and this is
  // materialPdf. What a route's sample divides by.
  double pdf(Vec3 wi, double materialPdf) const {
    return table ? mixture(tablePdf(wi), materialPdf) : materialPdf;
  }
  // The same from the two densities per unit solid angle.
  double mixture(double tableDensity, double materialPdf) const {
    return (1 - defensive) * tableDensity + defensive * materialPdf;
  }
};

// A route's sample is a BsdfSample whose `pdf` is the route's density at wi
// (LobeFrame::pdf), which the estimate divides by, and whose `misPdf` is the
// material's own sampling pdf there, which the MIS weights of both
// strategies take (the light sample's too, so the weights still sum to 1 at
// every direction and the estimate stays unbiased). Under MIS a table holds
// the material's sampling pdf at its bin's centre, so the two densities
// differ only by the view's offset within the bin; weights from the
// material's pdf spare every light sample a table lookup
// (renderer/README.md, "Lobe routes", has the measurements).

// The point a route samples with: a primary point (uniform in the square),
// or a point that already follows the route's table (a set dealt for it).
struct RoutePoint {
  Point2 value;
  bool followsTable = false;
};

// The sample of the route `lobe` at wo for the point p and the lobe-choice
// number uc: without a table the material's own sample(wo, uc, p); with one, a primary point
// is mapped by the table's inverse CDF, except that a share `defensive` of
// the square (u.x < defensive) goes to the material's own sample() and the
// rest, stretched over the square, through the table. A point that follows
// the table is used as it is where there is no defensive share; with one it
// is pulled back to the table's primary space (GridTarget::primaryOf) to be
// split there. f is the material's; with uniform primary points, wi
// follows the route's density. nullopt when no direction results.
std::optional<BsdfSample> sampleRoute(const Bsdf &bsdf, Vec3 wo, const LobeFrame &lobe,
                                      RoutePoint p, double uc);

// What the route measurement found for one bin (renderer/README.md, "Lobe
// routes"): the relative variance of a 16-point Owen-Sobol estimate of the
// reflected light under smooth lights, through the material's own sampler
// and through the table, summed over views spread across the bin.
struct LobeBinRoute {
  std::size_t material = 0;                 // index among the tabulated materials
  double thetaDegrees = 0, phiDegrees = 0;  // the bin's centre
  // Through the material's sample() and the table (0 when the routing
  // measures nothing).
  double classicVariance = 0, tableVariance = 0;
  bool table = false;  // whether the table serves the bin
};

class LobeTables {
 public:
  // Tables for every distinct DisneyBrdf among `materials`; other materials
  // get none. Throws std::invalid_argument for bins < 1 or a mix outside
  // [0, 1].
  LobeTables(const std::vector<std::shared_ptr<const Bsdf>> &materials,
             const LobeTablesConfig &config = {});

  // The frame for `material` at wo (shading frame, wo.z > 0); nullopt for a
  // material without tables.
  std::optional<LobeFrame> frame(const Bsdf *material, Vec3 wo) const;

  // Every table that serves (its bin's route is the table), material by
  // material and bin by bin: the contexts a backend is asked for.
  std::vector<const Target *> targets() const;
  // Every bin's route and its measurement, in the order of the tables.
  const std::vector<LobeBinRoute> &routes() const { return routes_; }
  std::size_t materials() const { return entries_.size(); }
  const LobeTableSettings &settings() const { return config_.settings; }

 private:
  struct Entry {
    const DisneyBrdf *material;
    bool anisotropic;
    std::vector<std::unique_ptr<GridTarget>> tables;  // theta-major, then phi
    std::size_t firstRoute;                           // its tables' routes in routes_
  };
  // Measures and sets the routes of e's bins (e is material `material`).
  void measureRoutes(const Entry &e, std::size_t material);
  // The bin of `e` that wo falls in (an index into e.tables), and the frame
  // of that bin's table at wo, whatever its route.
  std::size_t binIndex(const Entry &e, Vec3 wo) const;
  LobeFrame frameIn(const Entry &e, Vec3 wo, std::size_t index) const;
  LobeTablesConfig config_;
  // The inner edges of the theta bins as cosines and of the phi bins as
  // tangents, in increasing angle.
  std::vector<double> cosThetaEdges_, tanPhiEdges_;
  std::vector<Entry> entries_;
  std::vector<LobeBinRoute> routes_;
};

// The lobe tables a scene's renders share (Scene::lobeTables): built the
// first time a render asks for given materials and settings, then reused by
// every later render, repeat and study cell of the scene. Thread-safe.
class LobeTableCache {
 public:
  std::shared_ptr<const LobeTables> get(const std::vector<std::shared_ptr<const Bsdf>> &materials,
                                        const LobeTablesConfig &config);

 private:
  struct Item {
    std::vector<const Bsdf *> materials;
    LobeTablesConfig config;
    std::shared_ptr<const LobeTables> tables;
  };
  std::mutex mutex_;
  std::vector<Item> items_;
};

}  // namespace nuld
