// nuld: non-uniform low-discrepancy point sets and the renderer that uses them.
// The command line is documented in docs/usage.md; scripts and docs rely on it.

#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "backends/ranks.h"
#include "backends/set_cache.h"
#include "materials/disney_target.h"
#include "renderer/sampler_backend.h"
#include "sampler/diagnostics.h"
#include "sampler/enum_names.h"
#include "sampler/targets/target_family.h"
#include "sampler/targets/target_spec.h"
#include "scenes/scene_file.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"

namespace {

// The subcommand of `parent` named `word`; nullptr after saying on stderr,
// with the closest name and the choices (also `otherTopics`, help's own),
// that there is none ("nuld: error: PREFIX unknown subcommand ...").
CLI::App *subcommandNamed(CLI::App &parent, const std::string &word, const std::string &prefix,
                          const std::vector<std::string> &otherTopics = {}) {
  std::vector<std::string> names;
  for (CLI::App *sub : parent.get_subcommands({})) {
    if (sub->get_name() == word) return sub;
    names.push_back(sub->get_name());
  }
  names.insert(names.end(), otherTopics.begin(), otherTopics.end());
  std::cerr << "nuld: error: " << prefix << "unknown "
            << (otherTopics.empty() ? "subcommand" : "topic") << " '" << word << "'";
  if (const std::string near = nuld::closestName(word, names); !near.empty())
    std::cerr << " (did you mean '" << near << "'?)";
  std::cerr << "; expected " << nuld::joinAlternatives(names) << "\n";
  return nullptr;
}

// "  GRAMMAR  description", the description wrapped under a fixed column.
void printEntry(const std::string &grammar, const std::string &description) {
  constexpr std::size_t kColumn = 30, kWidth = 100;
  std::string line = "  " + grammar;
  line += line.size() + 2 <= kColumn ? std::string(kColumn - line.size(), ' ')
                                     : "\n" + std::string(kColumn, ' ');
  std::size_t col = kColumn;
  std::size_t pos = 0;
  while (pos < description.size()) {
    std::size_t end = description.find(' ', pos);
    if (end == std::string::npos) end = description.size();
    const std::string word = description.substr(pos, end - pos);
    if (col > kColumn && col + 1 + word.size() > kWidth) {
      line += "\n" + std::string(kColumn, ' ');
      col = kColumn;
    } else if (col > kColumn) {
      line += ' ';
      ++col;
    }
    line += word;
    col += word.size();
    pos = end + 1;
  }
  std::cout << line << "\n";
}

// `nuld help targets` and `nuld help backends`: the SPEC grammars that
// --target and --backend take, from the catalogues makeTarget and
// makeBackend refuse unknown names with.
bool printTopic(const std::string &topic) {
  if (topic == "targets") {
    std::cout << "Targets (--target SPEC): densities on the unit square, or on the sphere and\n"
                 "hemisphere through the equal-area map (docs/usage.md, \"Point sets\").\n\n";
    for (const auto &d : nuld::targetDescriptions()) printEntry(d.grammar, d.description);
    std::cout << "\nTarget families (nuld train --target family:...): a target for every gamma\n"
                 "in [0, 1]^k, what conditioned models learn.\n\n";
    for (const auto &d : nuld::targetFamilyDescriptions()) printEntry(d.grammar, d.description);
    return true;
  }
  if (topic == "backends") {
    // One registry; each word listed where it serves.
    const auto list = [](unsigned use) {
      for (const auto &e : nuld::backendRegistry()) {
        if (e.uses != use) continue;
        std::string help = e.help;
        if (!e.aliases.empty()) {
          help += " (also:";
          for (const auto &a : e.aliases) help += " " + e.spelling(a);
          help += ")";
        }
        if (e.shiftable) help += "; NAME+shift: every set shifted in primary space (unbiased)";
        printEntry(e.spelling(), help);
      }
    };
    std::cout << "Sampler backends (nuld render --backend, study render --backends, nuld bank,\n"
                 "Python's render; and study integrate --samplers):\n\n";
    list(nuld::kEverywhere);
    std::cout << "\nRenders only (the sets are made for the scene and kept in the set cache;\n"
                 "docs/usage.md, \"Comparison studies\"):\n\n";
    list(nuld::kRenders);
    std::cout << "\nstudy integrate only:\n\n";
    list(nuld::kIntegration);
    return true;
  }
  return false;
}

}  // namespace

int main(int argc, char **argv) {
  // Under mpirun or srun: one rank of a job (backends/ranks.h).
  const nuld::MpiSession mpi(argc, argv);
  const nuld::Ranks &ranks = nuld::Ranks::world();
  // Every rank loads the same scenes and maps; rank 0 alone says what it
  // warns about.
  if (!ranks.root()) nuld::setWarningHandler([](const std::string &) {});
  nuld::registerMaterialTargets();  // disney:... target specs
  // Neural lobe banks outlive the process in the set cache (set_cache.h).
  nuld::setLobeBankStore(std::make_shared<nuld::SetCacheLobeBankStore>());
  CLI::App app{"nuld: optimize, evaluate and render with non-uniform low-discrepancy point sets"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");
  app.set_version_flag("--version", NULD_VERSION);

  std::map<CLI::App *, nuld::cli::Runner> runners;
  auto add = [&](const char *name, const std::string &description, auto adder) {
    CLI::App *sub = app.add_subcommand(name, description);
    runners[sub] = adder(*sub);
  };
  add("generate", "Generate Sobol, Halton or random point sets, optionally mapped to a target",
      nuld::cli::addGenerate);
  add("map", "Map uniform point sets to a target by its inverse CDF", nuld::cli::addMap);
  add("eval", "Print discrepancies of a point-set file as 'NAME VALUE' lines", nuld::cli::addEval);
  add("export", "Write a point-set file's points as numpy .npy, CSV columns or UTK .dat",
      nuld::cli::addExport);
  add("optimize", "Optimize point sets for a target by gradient descent (Algorithm 1)",
      nuld::cli::addOptimize);
  add("train", "Train a neural generator for a target or target family (LibTorch)",
      nuld::cli::addTrain);
  add("plot", "Draw a point set (over its target density) to a PNG", nuld::cli::addPlot);
  add("spectrum", "Power spectrum of a point set: PNG image and radial-average CSV",
      nuld::cli::addSpectrum);
  add("render",
      "Render a scene (JSON or glTF file, or built in: " + nuld::builtInSceneList() +
          ") with a sampler backend to EXR + PNG",
      nuld::cli::addRender);
  add("compare", "Print mse and relmse of an image against a reference; write an error map",
      nuld::cli::addCompare);
  add("study", "Comparison studies: integration error, renders against references, reports",
      nuld::cli::addStudy);
  add("bank", "Make (or find in the set cache) a scene's learned sets and list them by pair",
      nuld::cli::addBank);
  add("cache", "The shared caches of sets and references: list, verify, remove, clear, path",
      nuld::cli::addCache);
  // --threads on every command that does work (the leaves of the command
  // tree): the cores TBB may use, for sharing a machine or timing.
  int threads = 0;
  const std::function<void(CLI::App &)> addThreads = [&](CLI::App &a) {
    const auto subs = a.get_subcommands({});
    if (subs.empty()) {
      a.add_option("--threads", threads, "cores to use (default: all)")->check(CLI::Range(1, 4096));
      return;
    }
    for (CLI::App *sub : subs) addThreads(*sub);
  };
  for (CLI::App *sub : app.get_subcommands({}))
    if (sub->get_name() != "cache") addThreads(*sub);
  CLI::App *help = app.add_subcommand(
      "help",
      "Show this help, a subcommand's (help SUB [SUB]), or the grammar of --target "
      "and --backend (help targets, help backends)");
  std::vector<std::string> helpTopic;
  help->add_option("subcommand", helpTopic, "e.g. optimize, or study render");

  // A first word that names no subcommand (a typo) gets its own message
  // rather than CLI11's "a subcommand is required".
  if (argc > 1 && argv[1][0] != '-' && !subcommandNamed(app, argv[1], "")) return 2;
  // An option given an empty value ("--target ''") would otherwise mean
  // "not given" and silently fall back to the default.
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    const bool emptyNext = i + 1 < argc && argv[i + 1][0] == '\0';
    if (word.size() > 1 && word[0] == '-' &&
        (word.back() == '=' || (emptyNext && word.find('=') == std::string::npos))) {
      std::cerr << "nuld: error: " << word.substr(0, word.find('='))
                << ": expected a value, got ''\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError &e) {
    // --help and --version end here too (exit code 0): CLI11 prints them.
    if (e.get_exit_code() == 0) return ranks.root() ? app.exit(e) : 0;
    // Every rank parsed the same words; one of them says what was wrong, in
    // the form of every other error, and every usage error exits 2
    // (docs/usage.md, "Conventions worth knowing").
    if (ranks.root()) std::cerr << "nuld: error: " << e.what() << " (--help lists the options)\n";
    return 2;
  }
  if (help->parsed()) {
    // "help study render" walks down the subcommands named. The formatter
    // is called directly: App::help() would show the parsed subcommand's
    // help, that is help's own.
    if (helpTopic.size() == 1 && printTopic(helpTopic[0])) return 0;
    CLI::App *topic = &app;
    std::string path = "nuld";
    for (const std::string &word : helpTopic) {
      topic = subcommandNamed(*topic, word, "help: ",
                              topic == &app ? std::vector<std::string>{"targets", "backends"}
                                            : std::vector<std::string>{});
      if (!topic) return 2;
      path += " " + word;
    }
    std::cout << topic->get_formatter()->make_help(topic, path, CLI::AppFormatMode::Normal);
    return 0;
  }
  // Only these split their work over the ranks of an MPI job. Any other
  // command runs unchanged on rank 0 alone, so that the job writes its files
  // once; the other ranks end at once.
  if (ranks.distributed()) {
    std::string words;
    for (CLI::App *sub = &app; sub && sub->get_subcommands().size() == 1;
         sub = sub->get_subcommands()[0])
      words += (words.empty() ? "" : " ") + sub->get_subcommands()[0]->get_name();
    if (words != "optimize" && words != "study render" && words != "study integrate") {
      if (!ranks.root()) return 0;
      std::cerr << "nuld: note: 'nuld " << words << "' does not split its work; it runs on rank 0 "
                << "alone (the other " << ranks.size() - 1
                << " ranks have nothing to do). Those that split: optimize, study render, "
                   "study integrate\n";
    }
  }
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
  try {
    for (auto &[sub, run] : runners)
      if (sub->parsed()) return run();
  } catch (const nuld::cli::UsageError &e) {
    // Found after parsing (an option that does not apply): still a usage
    // error, with CLI11's status.
    ranks.fail(e.what(), 2);
  } catch (const std::filesystem::filesystem_error &e) {
    // The library's text ("filesystem error: cannot create directories: ...
    // [path]") in the form of every other refusal: the path first.
    std::string what = e.path1().string() + ": " + e.code().message();
    if (std::string(e.what()).find("create director") != std::string::npos)
      what += " (cannot create the directory)";
    ranks.fail(what);
  } catch (const std::exception &e) {
    // In a job of several ranks this stops them all.
    ranks.fail(e.what());
  }
  return 0;
}
