#include "python/py_errors.h"

#include <pybind11/pybind11.h>

namespace fq::py {

void throw_if_error(const Status& s) {
  switch (s.code()) {
    case StatusCode::kOk:
      return;
    case StatusCode::kInvalidArgument:
    case StatusCode::kInvalidInput:
      throw pybind11::value_error(s.message());
    default:
      throw std::runtime_error(s.message());  // pybind11 raises RuntimeError
  }
}

void throw_if_file_error(const Status& s) {
  // fq_meshio reports unopenable and unwritable files as invalid arguments and content it
  // cannot decode as invalid input.
  if (s.code() == StatusCode::kInvalidArgument) {
    PyErr_SetString(PyExc_OSError, s.message().c_str());
    throw pybind11::error_already_set();
  }
  throw_if_error(s);
}

}  // namespace fq::py
