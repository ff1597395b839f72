// The extension module behind `import nuld` (tools/python/README.md). Every
// public function reads its call itself (args.h, Signature): its docstring
// carries the signature Python's help and inspect show, and what C++ throws
// reaches Python named by the function (ValueError, RuntimeError,
// MemoryError), never in the library's words.

#include "backends/set_cache.h"
#include "materials/disney_target.h"
#include "tools/python/args.h"

PYBIND11_MODULE(_nuld, m) {
  m.doc() = "nuld: non-uniform low-discrepancy point sets and a path tracer to test them";
  // The functions take (*args, **kwargs); their docstrings say their own
  // signatures (Signature::docstring).
  pybind11::options options;
  options.disable_function_signatures();
  nuld::registerMaterialTargets();  // `disney:...` target specs, as the CLI has them
  // Neural lobe banks in the set cache, as the CLI keeps them.
  nuld::setLobeBankStore(std::make_shared<nuld::SetCacheLobeBankStore>());
  nuld::python::bindArgs(m);
  nuld::python::bindPoints(m);
  nuld::python::bindRender(m);
  nuld::python::bindStudy(m);
  m.attr("__version__") = NULD_VERSION;  // the project's (CMakeLists.txt), as `nuld --version`
}
