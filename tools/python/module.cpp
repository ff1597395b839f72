// The extension module behind `import nuld` (tools/python/README.md). C++
// exceptions become Python's with the same message: std::invalid_argument
// ValueError, std::runtime_error RuntimeError (pybind11's own translation).

#include "materials/disney_target.h"
#include "tools/python/args.h"
#include "tools/study/set_cache.h"

PYBIND11_MODULE(_nuld, m) {
  m.doc() = "nuld: non-uniform low-discrepancy point sets and a path tracer to test them";
  nuld::registerMaterialTargets();  // `disney:...` target specs, as the CLI has them
  // Neural lobe banks in the set cache, as the CLI keeps them.
  nuld::setLobeBankStore(std::make_shared<nuld::study::SetCacheLobeBankStore>());
  nuld::python::bindArgs(m);
  nuld::python::bindPoints(m);
  nuld::python::bindRender(m);
  m.attr("__version__") = NULD_VERSION;  // the project's (CMakeLists.txt), as `nuld --version`
}
