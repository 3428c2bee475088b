// Python module: long renders' progress callbacks, Ctrl-C and work estimates (bindings.hpp).
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "bindings.hpp"

namespace par2d::python {
namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Without a callback, Ctrl-C is looked for at most this often: taking the GIL at every tile
// would stall the frame behind the other Python threads.
constexpr double kSignalCheckSeconds = 0.05;

}  // namespace

PyProgress::PyProgress(py::object callback) : callback_(std::move(callback)), last_check_(now_seconds()) {}

PyProgress::~PyProgress() {
  Py_XDECREF(type_);
  Py_XDECREF(value_);
  Py_XDECREF(traceback_);
}

par2d::ProgressFunction PyProgress::function() {
  return [this](const par2d::Progress& progress) { return call(progress); };
}

bool PyProgress::call(const par2d::Progress& progress) {
  if (callback_.is_none()) {
    const double now = now_seconds();
    if (now - last_check_ < kSignalCheckSeconds) return true;
    last_check_ = now;
  }
  py::gil_scoped_acquire gil;
  if (type_ != nullptr) return false;
  if (PyErr_CheckSignals() != 0) {
    PyErr_Fetch(&type_, &value_, &traceback_);
    return false;
  }
  if (callback_.is_none()) return true;
  PyObject* result = PyObject_CallFunction(callback_.ptr(), "KK", static_cast<unsigned long long>(progress.tiles_done),
                                           static_cast<unsigned long long>(progress.tiles));
  if (result == nullptr) {
    PyErr_Fetch(&type_, &value_, &traceback_);
    return false;
  }
  const bool stop = result == Py_False;
  Py_DECREF(result);
  return !stop;
}

void PyProgress::finish(const par2d::Status& status) {
  if (type_ != nullptr) {
    PyErr_Restore(type_, value_, traceback_);
    type_ = value_ = traceback_ = nullptr;
    throw py::error_already_set();
  }
  check(status);
}

py::object to_progress(const py::object& obj) {
  if (obj.is_none() || PyCallable_Check(obj.ptr())) return obj;
  bad_argument("progress", "needs a callable or None, got " + describe(obj));
}

py::dict estimate_dict(const par2d::WorkEstimate& e) {
  py::dict d;
  d["samples"] = e.samples;
  d["bounce"] = e.bounce;
  d["scalar"] = e.scalar;
  d["raycast"] = e.raycast;
  d["total"] = e.total;
  return d;
}

double to_work_limit(const py::object& obj) {
  const double limit = to_double(obj, "work_limit");
  if (!(std::isfinite(limit) && limit >= 0.0))
    bad_argument("work_limit", "needs a finite number >= 0 (0: no limit), got " + describe(obj));
  return limit;
}

}  // namespace par2d::python
