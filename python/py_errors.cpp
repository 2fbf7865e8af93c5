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
  // fq_io reports files it cannot find, open, read or write as kIoError (and a few file
  // problems as invalid arguments), content it cannot decode as invalid input.
  if (s.code() == StatusCode::kIoError || s.code() == StatusCode::kInvalidArgument) {
    PyErr_SetString(PyExc_OSError, s.message().c_str());
    throw pybind11::error_already_set();
  }
  throw_if_error(s);
}

}  // namespace fq::py
