// pybind11 binding of the paper module (funnel::paper): one figure's data and check, computed by
// the same code as `funnel paper`; documented in python/funnel/_api.py (paper_figure).
#include <pybind11/pybind11.h>

#include <atomic>
#include <string>

#include "funnel/paper/cases.hpp"
#include "funnel/paper/figures.hpp"
#include "funnel/paper/records.hpp"
#include "convert.hpp"

namespace py = pybind11;

namespace {

/// The figure of the TOML definition at `path`: {"id", "kind", "title", "caption", "csv" (the
/// CSV text `funnel paper` writes), "meta" and "check" (JSON texts)}. Progress goes to
/// `progress` (a callable (done, total), or None); Ctrl-C is honoured when the figure is done.
py::dict paper_figure(const std::string& path, bool quick, int threads, const py::object& progress) {
  funnel::paper::FigureSpec fig;
  funnel::paper::FigureData data;
  std::atomic<bool> cancel{false};  // the figure's runs do not watch it: Ctrl-C counts at the end
  try {
    fig = funnel::paper::load_figure(path, quick);
    funnel::py_convert::run_reporting(progress, cancel, [&](const funnel::Progress& report) {
      data = funnel::paper::compute_figure(fig, threads, report);
    });
  } catch (const funnel::paper::InputError& e) {
    throw py::value_error(e.what());
  }
  py::dict d;
  d["id"] = fig.id;
  d["kind"] = fig.kind;
  d["title"] = fig.title;
  d["caption"] = fig.caption;
  d["csv"] = data.csv;
  d["meta"] = data.extra.dump();
  d["check"] = data.check.dump();
  return d;
}

}  // namespace

void bind_paper(py::module_& m) {
  m.def("paper_figure", &paper_figure, py::arg("path"), py::arg("quick"), py::arg("threads"), py::arg("progress"));
  m.attr("source_paper_dir") = FUNNEL_PAPER_DIR;
}
