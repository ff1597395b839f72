// nuld export: a point-set file's points as a numpy array (.npy), CSV
// columns (numpy.loadtxt would merge a text file's instances) or UTK's .dat.

#include <cstdio>

#include "sampler/io/atomic_file.h"
#include "sampler/io/pointset_io.h"
#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addExport(CLI::App &app) {
  struct Options {
    std::string file, output;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->file, "point-set file (text or binary)")->required();
  app.add_option(
         "-o,--output", o->output,
         "OUT.npy (float64, shape (instances, N, 2)), OUT.csv (columns instance,x,y) or OUT.dat "
         "(UTK's text format: sets separated by a line '#')")
      ->required();
  app.footer(
      "In Python: numpy.load('OUT.npy'), or numpy.loadtxt('OUT.csv', delimiter=',',\n"
      "skiprows=1). The metadata stays in the point-set file (nuld eval reads it).");
  return [o] {
    checkDestination(o->output);
    const PointSet set = readPointSet(o->file);
    exportPointSet(o->output, set);
    std::fprintf(stderr, "wrote %zu x %zu points to %s\n", set.instances(), set.n,
                 o->output.c_str());
    return 0;
  };
}

}  // namespace nuld::cli
