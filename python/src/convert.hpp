// Conversions shared by the binding files: numpy columns, lists of text, and long runs that
// report progress to Python.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "funnel/ensemble.hpp"
#include "funnel/grid.hpp"
#include "funnel/params.hpp"

namespace funnel::py_convert {

namespace py = pybind11;

/// A 1-D numpy array filled from `n` values of `get(i)`.
template <typename T, typename Get>
py::array_t<T> column(std::size_t n, Get get) {
  py::array_t<T> a(static_cast<py::ssize_t>(n));
  auto w = a.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) w(static_cast<py::ssize_t>(i)) = get(i);
  return a;
}

/// A list of str from `n` values of `get(i)` (the Python layer makes it a numpy str array).
template <typename Get>
py::list text_column(std::size_t n, Get get) {
  py::list l;
  for (std::size_t i = 0; i < n; ++i) l.append(std::string(get(i)));
  return l;
}

/// Runs `work(report)` without the GIL; every call of `report(done, total)` goes to `progress`
/// (a Python callable, or None) and checks for Ctrl-C. Ctrl-C, or an error the callback raises,
/// sets `cancel` (work that watches it stops early; later reports are dropped) and is raised
/// once `work` returns. The work runs in its own thread while this (the caller's) thread looks
/// for Ctrl-C ten times a second: a unit of work may take seconds (a 3D ensemble's task of 128
/// balls), and Python's signal handlers run only in its main thread.
template <class Work>
void run_reporting(const py::object& progress, std::atomic<bool>& cancel, Work work) {
  std::optional<py::error_already_set> error;  // set with the GIL held
  const auto fail = [&](py::error_already_set& e) {
    if (!error) error.emplace(std::move(e));
    cancel = true;
  };
  const funnel::Progress report = [&](std::int64_t done, std::int64_t total) {
    if (cancel.load()) return;
    py::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress.is_none()) progress(done, total);
    } catch (py::error_already_set& e) {
      fail(e);
    }
  };
  {
    py::gil_scoped_release nogil;
    std::mutex m;
    std::condition_variable finished_cv;
    bool finished = false;
    std::exception_ptr failure;
    std::thread worker([&] {
      try {
        work(report);
      } catch (...) {
        failure = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(m);
      finished = true;
      finished_cv.notify_all();
    });
    std::unique_lock<std::mutex> lock(m);
    while (!finished_cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return finished; })) {
      if (cancel.load()) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) {
          py::error_already_set e;
          fail(e);
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
    if (failure) std::rethrow_exception(failure);
  }
  if (error) throw *error;
}

/// The sink of one trajectory run from Python without the GIL (simulate): it passes the events
/// on to `log` (or drops them), and after every 256th collision takes the GIL to look for
/// Ctrl-C, which ends the run there (finished()); raise_if_interrupted() then raises it. A
/// trajectory of millions of collisions could not be interrupted. Sink is funnel::EventSink or
/// funnel::EventSink3, Event its event.
template <class Sink, class Event>
class InterruptSink final : public Sink {
 public:
  explicit InterruptSink(Sink* log) : log_(log) {}
  void record(const Event& e) override {
    if (log_ != nullptr) log_->record(e);
  }
  bool records() const override { return log_ != nullptr; }
  bool finished() const override {
    if (error_) return true;
    if ((++asked_ & 255) != 0) return false;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) error_.emplace();
    return error_.has_value();
  }
  /// Call with the GIL held, once the run is over.
  void raise_if_interrupted() {
    if (error_) throw std::move(*error_);
  }

 private:
  Sink* log_;
  mutable std::uint64_t asked_ = 0;
  mutable std::optional<py::error_already_set> error_;
};

/// Runs `work(report)` without the GIL, with `options.cancel` (EnsembleOptions or
/// Ensemble3Options) watching for Ctrl-C: every finished work unit reports to `progress` (a
/// Python callable (done, total), or None) and checks for Ctrl-C, which cancels the rest of the
/// run and raises KeyboardInterrupt.
template <class Options, class Work>
void run_interruptible(Options& options, const py::object& progress, Work work) {
  std::atomic<bool> cancel{false};
  run_reporting(progress, cancel, [&](const funnel::Progress& report) {
    options.cancel = &cancel;
    work(report);
    options.cancel = nullptr;
  });
}

/// Checks a sweep's axes before the grid is built: every value settable (an integral
/// max-collisions: expand_grid would skip 1.5 and run uncapped) and at most
/// funnel::max_sweep_points points, as funnel sweep; ValueError otherwise.
inline void check_sweep_axes(const std::vector<funnel::Axis>& axes) {
  for (const funnel::Axis& a : axes) {
    for (const double v : a.values) {
      funnel::Params probe = funnel::default_params();
      if (const auto err = funnel::set_parameter_checked(probe, a.name, v)) throw py::value_error(err->message());
    }
  }
  const double points = funnel::grid_points(axes);
  if (points > funnel::max_sweep_points) {
    throw py::value_error("invalid grid: " + funnel::format_number(points) +
                          " points; valid range is at most 2e+06 points (as funnel sweep): split it into several runs");
  }
}

/// Every parameter of the space by its output key, as the CLI's "params": None for one that a
/// geometry file leaves unused (funnel::reported_value).
inline py::dict params_dict(const funnel::Params& p, funnel::Space space = funnel::Space::TwoD) {
  py::dict d;
  for (const funnel::ParameterInfo& info : funnel::parameters(space)) {
    if (info.integer) {
      d[py::str(info.key())] = static_cast<std::int64_t>(info.get(p));
    } else {
      const double v = funnel::reported_value(info, p);
      d[py::str(info.key())] = std::isnan(v) ? py::object(py::none()) : py::object(py::float_(v));
    }
  }
  return d;
}

/// The parameter columns of a sweep's points into `d`, in the order of the CLI's CSV: NaN for
/// one that a geometry file leaves unused.
inline void add_param_columns(py::dict& d, const std::vector<funnel::Params>& points, funnel::Space space) {
  const std::size_t n = points.size();
  for (const funnel::ParameterInfo& info : funnel::parameters(space)) {
    if (!info.option) continue;
    if (info.integer) {
      d[py::str(info.key())] =
          column<std::int64_t>(n, [&](std::size_t i) { return static_cast<std::int64_t>(info.get(points[i])); });
    } else {
      d[py::str(info.key())] = column<double>(n, [&](std::size_t i) { return funnel::reported_value(info, points[i]); });
    }
  }
}

}  // namespace funnel::py_convert
