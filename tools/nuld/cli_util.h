#pragma once
// Small helpers shared by the subcommands.

#include <CLI/CLI.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/ready_backend.h"
#include "renderer/render.h"
#include "sampler/enum_names.h"
#include "sampler/optimize/resumable_run.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"
#include "scenes/scene_file.h"

namespace nuld::cli {

// The target named on the command line, else the one recorded in the file's
// metadata, else uniform. A recorded target that cannot be opened here (a
// map under another asset root) is an error naming `file` and what to pass;
// a --target whose content differs from the recorded one is warned about.
std::unique_ptr<Target> targetFor(const std::string &spec, const PointSet &set,
                                  const std::string &file);

// Maps every point of `set` through the target's inverse CDF.
void mapByInverseCdf(PointSet &set, const Target &target);

// "W" or "WxH" (--res), each side in [1, 32768]; throws std::invalid_argument
// quoting the text and the expected form. The --res options check it when
// parsed (parsedBy), so a bad value exits 2.
// --res W or WxH; W alone (height 0) keeps the scene's aspect.
struct Resolution {
  int width = 0, height = 0;
};
Resolution parseResolution(const std::string &text);
// --res and --res-scale of a render-like command into `change` (--res-scale
// refused beside --res), the one reading render and bank share.
void applyResolution(const CLI::App &app, const std::string &res, double scale,
                     RenderOverrides &change);

// The flags every resumable command shares, with the same names and wording:
// --checkpoint-every (units of `unit`, e.g. "epochs"; `alsoDoes` adds what
// else happens then), --resume, --stop-after and -q.
void addRunFlags(CLI::App &app, RunFlags &flags, const std::string &unit,
                 const std::string &alsoDoes = "");
// A command line the command refuses as written: an option that does not
// apply, a value outside an option's grammar. It exits 2 as CLI11's own
// refusals do, however late it is found (docs/usage.md, "Conventions worth
// knowing"); a well-formed command that cannot be carried out (a file that
// does not exist or does not parse, a failure while running) exits 1.
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The check of an option whose value `parse` reads (a backend word, a
// target's family, a size list): its std::invalid_argument is the option's
// refusal, at parse time. `parse` must only read the text: files the value
// names are opened when the command runs, and failing then exits 1.
template <class F>
CLI::Validator parsedBy(F parse) {
  return CLI::Validator(
      [parse](std::string &text) {
        try {
          parse(text);
          return std::string();
        } catch (const std::invalid_argument &e) {
          return std::string(e.what());
        }
      },
      "");
}

// The check of an option that names a value of `names` (aliases included):
// the help lists the names as {a,b,c}; anything else is refused with the
// table's message.
template <class E, std::size_t N>
CLI::Validator oneOf(const EnumTable<E, N> &names) {
  CLI::Validator check = parsedBy([names](const std::string &text) { names.parse(text); });
  check.description(CLI::detail::generate_set(names.names()));
  return check;
}

// An option that names a value of `names`, parsed once, when given, into
// `value` (an E, or an optional<E> left unset when the option is not given),
// with oneOf's check and help.
template <class E, std::size_t N, class Value>
CLI::Option *addNamedOption(CLI::App &app, const std::string &name, Value &value,
                            const EnumTable<E, N> &names, const std::string &help) {
  return app
      .add_option_function<std::string>(
          name, [&value, &names](const std::string &word) { value = names.parse(word); }, help)
      ->check(oneOf(names));
}

// The grammar checks of options that several commands share: a target spec's
// family (checkTargetFamily), a render backend word that makes no sets
// (parseBackend) and any word of `nuld render --backend` (those that make
// their sets included).
CLI::Validator targetFamily();
CLI::Validator backendWord();
CLI::Validator studyBackendWord();

// The one rule for options that do not apply: when `applies` is false, the
// first of `options` the user gave is refused as "COMMAND: OPTION applies to
// WHEN only" (a UsageError), rather than silently ignored.
void onlyWhen(const CLI::App &app, bool applies, std::initializer_list<const char *> options,
              const std::string &when);

// --assets, when given: it must name a directory, and apply (`used`; `when`
// says to what, as onlyWhen's message does).
void checkAssets(const CLI::App &app, const std::string &assets, bool used,
                 const std::string &when);
inline const std::string kSceneFilesOnly = "scene files (the built-in scenes need no assets)";

// A whole number >= 0 that fits 64 bits (seeds): refuses "-1", "1.5" and
// "1e30" by quoting the text, where CLI11's range check would print its
// bound in 300 digits (and an unsigned option would wrap -1 to 2^64 - 1).
CLI::Validator wholeNumber();

// A finite number > 0, or >= 0: the refusal quotes the text (CLI11's own
// PositiveNumber and NonNegativeNumber print their bound in 300 digits).
// A whole number in [lo, hi], or a number in [lo, hi]: the refusal quotes
// the text and states the range ("from 1 to 2^20"), where CLI11's own range
// check says "Value 0 not in range".
CLI::Validator wholeNumberIn(std::int64_t lo, std::int64_t hi);
CLI::Validator numberIn(double lo, double hi);
CLI::Validator positiveNumber();
CLI::Validator nonNegativeNumber();

// The lobe options of the commands that render (renderer/README.md,
// "Sampling contexts" and "Lobe routes"), read into `change`: --lobe-mix
// (the tables' density), --lobe-routes (measured or table),
// --lobe-defensive (the defensive share) and --lobe-bounces (how many
// bounces sample tables).
void addLobeOptions(CLI::App &app, RenderOverrides &change);
inline constexpr std::initializer_list<const char *> kLobeOptionNames = {
    "--lobe-mix", "--lobe-routes", "--lobe-defensive", "--lobe-bounces"};

// --lobe-choice, how the scene's Disney materials pick a lobe to sample
// (materials/disney.h, LobeChoice), and --env-importance, what weighs the
// environment map's sampling in place of the scene's (image_targets.h),
// read into `choices` (left as they are when not given).
void addSceneChoiceOptions(CLI::App &app, SceneChoices &choices);
// --lobe-choice alone (study integrate, which has no scene).
void addLobeChoiceOption(CLI::App &app, LobeChoice &choice);

// "WHAT: uniform, bilinear:w00,w10,w01,w11, ... (nuld help targets)": every
// target grammar makeTarget knows, for a --target option's help.
std::string targetOptionHelp(const std::string &what);

// The options of the sets the study's backends make (optimized,
// optimized-bsdf, ...: backends/ready_backend.h), the same on nuld render
// and nuld study render.
void addSetOptions(CLI::App &app, SetSettings &s);
// The directory where those sets, and the checkpoints of sets being made,
// live: the set cache's (s.cacheDir, else $NULD_CACHE, ...).
std::string setsDirectory(const SetSettings &s);
// What an interrupted command that makes sets says (InterruptNote's note).
std::string setsInterruptNote(const std::string &setsDir);
inline constexpr std::initializer_list<const char *> kSetOptionNames = {
    "--opt-instances", "--opt-epochs",    "--opt-lobe-epochs",
    "--opt-nested",    "--opt-objective", "--opt-union-weight"};

}  // namespace nuld::cli
