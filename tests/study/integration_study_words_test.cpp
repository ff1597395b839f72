// The integration study's samplers beyond the classic ones
// (integration_study_test.cpp): neural sets dealt as renders deal them, a
// model's integrand, what every word means, banks from files, bad input.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>

#include "materials/disney_target.h"
#include "materials/sphere_map.h"
#include "sampler/io/image_io.h"
#include "sampler/io/pointset_io.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/temp_dir.h"
#include "tests/study/integration_cases.h"
#include "tests/study/synthetic_map.h"
#include "tools/study/csv_table.h"
#include "tools/study/integrands.h"
#include "tools/study/integration_study.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using nuld::test::TempDir;
using test::field;
using test::findRow;
using test::quickOptions;
using test::readCsv;
using test::syntheticMap;
using test::value;
constexpr double kPi = std::numbers::pi;

// Independent points over many instances: every integrand's bias (also the
// sphere ones, also through the BRDF's lobe sampling) is within 4 standard
// errors of 0 (a false alarm has probability ~6e-5 per row; seeds are fixed).
// A lobe model's sets are dealt out as the renderer deals them, each shifted
// in the table's primary space (its CDF map), whether or not the word says
// +shift (one word, one meaning in every command): one row, named +shift,
// unbiased (within 4 standard errors, 256 sets of 64), and a note saying
// so; a shift on an integrand without a CDF map is refused.
TEST(IntegrationStudyRun, ShiftedNeuralSetsAreDealtAsTheRendererDealsThem) {
  registerMaterialTargets();
  TempDir dir;
  NeuralSettings lobe;
  lobe.n = 64;
  lobe.hidden = 8;
  lobe.family = "family:disney";  // the supplement's lobe over the view
  const std::string model = (dir / "lobe.nuldnet").string();
  NeuralGenerator(lobe).save(model);
  IntegrateOptions o = quickOptions(dir / "out");
  o.integrands = {"disney*cosines:theta=45"};
  o.samplers = {"sobol-tabulated", "neural:" + model, "neural:" + model + "+shift"};
  o.ns = {64};
  o.optimizedInstances = 256;
  const IntegrateSummary summary = runIntegrateStudy(o);
  EXPECT_TRUE(std::any_of(summary.notes.begin(), summary.notes.end(), [](const std::string &n) {
    return n.find("neural:lobe: a lobe family's sets are dealt shifted") != std::string::npos;
  }));
  const CsvTable t = readCsv(o.outDir);
  EXPECT_EQ(t.rows().size(), 2u);  // sobol-tabulated and the one neural row
  EXPECT_FALSE(findRow(t, o.integrands[0], "neural:lobe", 64));
  const auto *row = findRow(t, o.integrands[0], "neural:lobe+shift", 64);
  ASSERT_TRUE(row);
  EXPECT_EQ(field(t, *row).at("instances"), "256");
  EXPECT_LT(std::abs(value(t, *row, "bias")), 4 * value(t, *row, "bias_stderr"));

  NeuralSettings ns;
  ns.n = 16;
  ns.hidden = 8;
  ns.family = "quarterdisc";  // a closed-form target: no CDF map
  const std::string qd = (dir / "qd.nuldnet").string();
  NeuralGenerator(ns).save(qd);
  o.integrands = {"quarterdisc*bilinear"};
  o.samplers = {"neural:" + qd + "+shift"};
  o.ns = {16};
  o.optimizedInstances = 8;
  o.outDir = dir / "out2";
  try {
    runIntegrateStudy(o);
    FAIL() << "a shift without a CDF map was accepted";
  } catch (const std::exception &e) {
    EXPECT_NE(std::string(e.what()).find("no CDF map"), std::string::npos) << e.what();
  }
}

TEST(IntegrationStudyRun, NeuralModelServesTheIntegrandOfItsTarget) {
  TempDir dir;
  NeuralSettings ns;
  ns.n = 16;
  ns.hidden = 8;
  ns.family = "quarterdisc";
  const std::string model = (dir / "qd.nuldnet").string();
  NeuralGenerator(ns).save(model);  // untrained: inverse-CDF Sobol rotated by z
  IntegrateOptions o = quickOptions(dir / "out");
  o.integrands = {"gaussian*step", "quarterdisc*bilinear"};
  o.samplers = {"sobol"};
  o.neuralModels = {model};
  o.optimizedInstances = 8;
  runIntegrateStudy(o);
  const CsvTable t = readCsv(o.outDir);
  const auto *row = findRow(t, "quarterdisc*bilinear", "neural:qd", 16);
  ASSERT_TRUE(row);
  EXPECT_EQ(field(t, *row).at("instances"), "8");
  EXPECT_FALSE(findRow(t, "gaussian*step", "neural:qd", 16));
  EXPECT_LT(value(t, *row, "rel_rmse"), 0.1);

  // A model of another target matches no integrand.
  ns.family = "gaussian:0.2,0.3,0.1";
  const std::string other = (dir / "g.nuldnet").string();
  NeuralGenerator(ns).save(other);
  o.neuralModels = {other};
  try {
    runIntegrateStudy(o);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("matches none"), std::string::npos) << e.what();
  }
}

// The words mean what they mean in nuld render, one row each: `sobol` is
// each sampler's own mapping (the BRDF's sample() on a lobe integrand),
// `sobol-tabulated` the tabulated lobe (made on lobe integrands only); the
// default is every classic word with its -tabulated, and optimized; words
// that serve renders only are refused, naming where they serve; the old
// -lobes words are refused naming the new ones.
TEST(IntegrationStudySamplers, WordsMeanWhatTheyMeanInRenders) {
  const auto choices = parseSamplers({"sobol", "halton-tabulated", "random", "gbn"}, {});
  ASSERT_EQ(choices.size(), 4u);
  EXPECT_EQ(choices[0].name, "sobol");
  EXPECT_FALSE(choices[0].tabulated);
  EXPECT_EQ(choices[1].name, "halton-tabulated");
  EXPECT_TRUE(choices[1].tabulated);
  EXPECT_EQ(choices[1].kind, SamplerChoice::Kind::Classic);
  EXPECT_EQ(choices[1].sequence, SequenceKind::Halton);
  EXPECT_EQ(choices[2].name, "independent");
  EXPECT_EQ(choices[3].kind, SamplerChoice::Kind::BlueNoise);
  // A classic word carries its randomization: lattice its shift, and
  // lattice-baker the shift folded by the baker's transform.
  const auto lattices = parseSamplers({"lattice", "lattice-baker"}, {});
  EXPECT_EQ(lattices[0].scramble, Scramble::CranleyPatterson);
  EXPECT_EQ(lattices[1].scramble, Scramble::Baker);
  EXPECT_EQ(lattices[1].sequence, SequenceKind::Lattice);
  std::vector<std::string> defaults;
  for (const SamplerChoice &c : parseSamplers({}, {})) defaults.push_back(c.name);
  EXPECT_EQ(defaults,
            (std::vector<std::string>{"independent", "independent-tabulated", "sobol",
                                      "sobol-tabulated", "halton", "halton-tabulated", "stratified",
                                      "pmj02", "lattice", "lattice-baker", "optimized"}));
  for (const char *word : {"optimized-bsdf", "optimized-both+shift", "optimized+shift"})
    EXPECT_THROW(parseSamplers({word}, {}), std::invalid_argument) << word;
  try {
    parseSamplers({"optimized-uniform"}, {});
    FAIL();
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("serves renders only"), std::string::npos) << e.what();
  }
  try {
    parseSamplers({"sobol-lobes"}, {});
    FAIL() << "sobol-lobes was accepted";
  } catch (const std::invalid_argument &e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("is now 'sobol'"), std::string::npos) << what;
    EXPECT_NE(what.find("'sobol-tabulated'"), std::string::npos) << what;
  }
}

// The renderer's bank words take sets from files: sets for an integrand's
// own target serve that integrand (one estimate per instance, or shifted in
// primary space through its CDF map); uniform sets serve every integrand,
// shifted per instance and mapped by its inverse CDF. Rows are named by the
// files' stems, at the files' N; shifted estimates are unbiased.
TEST(IntegrationStudyRun, BankWordsTakeSetsFromFiles) {
  registerMaterialTargets();
  TempDir dir;
  const auto lobe = makeTarget("disney:theta=20");
  PointSet own = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 4}, 16, 4);
  for (Point2 &p : own.points) p = lobe->invert(p).x;
  own.metadata["target"] = lobe->spec();
  writePointSet((dir / "lobe20.txt").string(), own);
  writePointSet((dir / "uniform.txt").string(),
                generatePointSet({SequenceKind::Sobol, Scramble::Owen, 5}, 32, 4));
  IntegrateOptions o = quickOptions(dir / "out");
  o.integrands = {"disney*cosines", "quarterdisc*bilinear"};
  o.samplers = {"optimized:" + (dir / "lobe20.txt").string(),
                "shifted:" + (dir / "lobe20.txt").string(),
                "points:" + (dir / "uniform.txt").string()};
  o.optimizedInstances = 64;
  runIntegrateStudy(o);
  const CsvTable t = readCsv(o.outDir);
  // lobe20 at theta 20 only (twice: plain and shifted); uniform on all four.
  ASSERT_EQ(t.rows().size(), 2u + 4u);
  const auto *plain = findRow(t, "disney*cosines:theta=20", "optimized:lobe20", 16);
  const auto *shifted = findRow(t, "disney*cosines:theta=20", "shifted:lobe20", 16);
  ASSERT_TRUE(plain && shifted);
  EXPECT_EQ(field(t, *plain).at("instances"), "4");
  EXPECT_EQ(field(t, *shifted).at("instances"), "64");
  EXPECT_FALSE(findRow(t, "disney*cosines:theta=45", "optimized:lobe20", 16));
  for (const char *in : {"disney*cosines:theta=20", "disney*cosines:theta=45",
                         "disney*cosines:theta=70", "quarterdisc*bilinear"})
    EXPECT_TRUE(findRow(t, in, "optimized:uniform", 32)) << in;
  for (const auto &r : t.rows()) {
    if (field(t, r).at("instances") == "64") {
      EXPECT_LT(std::abs(value(t, r, "bias")), 4 * value(t, r, "bias_stderr")) << r[0] << r[2];
    }
  }
}

TEST(IntegrationStudyRun, BadInputIsAClearError) {
  TempDir dir;
  EXPECT_EQ(parseNList("16, 50,16"), (std::vector<std::size_t>{16, 50}));
  for (const char *bad : {"", "16,abc", "0", "16,,32", "16,", "-4", "1e3"})
    EXPECT_THROW(parseNList(bad), std::invalid_argument) << bad;
  try {
    parseNList("16,x");
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("--n"), std::string::npos);
  }
  const auto fails = [&](IntegrateOptions o, const std::string &mention) {
    try {
      runIntegrateStudy(o);
      ADD_FAILURE() << "expected an error mentioning " << mention;
    } catch (const std::exception &e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
  };
  IntegrateOptions o = quickOptions(dir / "out");
  o.integrands = {"gaussian*step"};
  IntegrateOptions a = o;
  a.integrands = {"gausian*step"};
  fails(a, "--integrands");
  IntegrateOptions b = o;
  b.samplers = {"sobel"};
  fails(b, "--samplers");
  IntegrateOptions c = o;
  c.instances = 1;
  fails(c, "--instances");
  IntegrateOptions d = o;
  d.neuralModels = {(dir / "missing.nuldnet").string()};
  fails(d, "--neural");
  IntegrateOptions e = o;
  e.neuralModels = {dir.write("junk.nuldnet", "not a model")};
  fails(e, "--neural");
  NeuralSettings narrow;
  narrow.n = 16;
  narrow.hidden = 8;
  narrow.family = "quarterdisc";
  narrow.offsetRange = 0.25;
  IntegrateOptions f = o;
  f.integrands = {"quarterdisc*bilinear"};
  f.neuralModels = {(dir / "narrow.nuldnet").string()};
  NeuralGenerator(narrow).save(f.neuralModels[0]);
  fails(f, "--offset-range");
  EXPECT_FALSE(fs::exists(integrateCsvPath(o.outDir)));  // nothing written on bad input
}

}  // namespace
}  // namespace nuld::study
