// nuld study: the comparison studies (integration error, scene renders against
// references) and the report that gathers their CSV into plots and HTML.

#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addStudy(CLI::App &app) {
  app.require_subcommand(1);
  struct Sub {
    CLI::App *app;
    Runner run;
  };
  auto subs = std::make_shared<std::vector<Sub>>();
  auto add = [&](const char *name, const char *description, auto adder) {
    CLI::App *sub = app.add_subcommand(name, description);
    subs->push_back({sub, adder(*sub)});
  };
  add("integrate",
      "Integration error against N for product integrands in 2D and on the sphere (CSV + plots)",
      addStudyIntegrate);
  add("render", "Scenes against references: MSE against spp and seconds (CSV, plots, HTML)",
      addStudyRender);
  add("report", "Rebuild the plots and the HTML report of a study directory", addStudyReport);
  return [subs] {
    for (const Sub &s : *subs)
      if (s.app->parsed()) return s.run();
    return 1;
  };
}

}  // namespace nuld::cli
