// The studies' statistics for Python (tools/python/README.md, "Studies"):
// nuld.study and a user's own loops summarize repeats as the CLI's studies
// do (tools/study/statistics.h).

#include <vector>

#include "tools/python/args.h"
#include "tools/python/bindings.h"
#include "tools/study/statistics.h"

namespace nuld::python {

void bindStudy(py::module_ &m) {
  defFunction(
      m, "mean_and_error", {"mean_and_error", {Param("values")}},
      [](py::object values) {
        const std::vector<double> v = numbers(values, {"mean_and_error", "values"});
        const study::MeanAndError e = study::meanAndError(v);
        py::dict d;
        d["mean"] = e.mean, d["std"] = e.std, d["stderr"] = e.stderr_;
        return d;
      },
      "the mean, the sample standard deviation (n - 1) and the standard error of the mean of "
      "repeated measurements, as the studies report them (deviation and error 0 for one value)");
  defFunction(
      m, "ratio_of_means",
      {"ratio_of_means", {Param("a"), Param("a_stderr"), Param("b"), Param("b_stderr")}},
      [](py::object a, py::object ae, py::object b, py::object be) {
        const std::string f = "ratio_of_means";
        const study::Ratio r =
            study::ratioOfMeans(number(a, {f, "a"}), number(ae, {f, "a_stderr"}),
                                number(b, {f, "b"}), number(be, {f, "b_stderr"}));
        py::dict d;
        d["ratio"] = r.value, d["stderr"] = r.stderr_;
        d["verdict"] = study::verdictName(study::verdictOf(r.value, r.stderr_));
        return d;
      },
      "a / b of two independent means with the ratio's standard error to first order, and the "
      "studies' verdict: 'better' or 'worse' when the ratio is more than two standard errors "
      "from 1, else 'tie'; 'n/a' when the error is 0 (one repeat) or b is not positive");
}

}  // namespace nuld::python
