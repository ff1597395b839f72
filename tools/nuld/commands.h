#pragma once
// Subcommands of the `nuld` program. Each registers its options on the parser
// and returns the function that runs it once the command line is parsed.

#include <CLI/CLI.hpp>
#include <functional>

namespace nuld::cli {

using Runner = std::function<int()>;

Runner addGenerate(CLI::App &app);
Runner addEval(CLI::App &app);
Runner addExport(CLI::App &app);
Runner addPlot(CLI::App &app);
Runner addSpectrum(CLI::App &app);
Runner addOptimize(CLI::App &app);
Runner addTrain(CLI::App &app);
Runner addMap(CLI::App &app);
Runner addRender(CLI::App &app);
Runner addCompare(CLI::App &app);
Runner addStudy(CLI::App &app);
Runner addCache(CLI::App &app);
Runner addBank(CLI::App &app);
// The study's parts (cmd_study_*.cpp).
Runner addStudyIntegrate(CLI::App &app);
Runner addStudyRender(CLI::App &app);
Runner addStudyReport(CLI::App &app);

}  // namespace nuld::cli
