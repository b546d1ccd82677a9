// Text signatures for inspect.signature (signatures.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace libwave_python {

// Gives every function and method of `m` (and of its classes) a text signature that
// inspect.signature reads — parameter names, kinds and defaults, from pybind11's own
// first docstring line — keeping that typed line and the docstring as __doc__; and makes
// pybind11's refusal of a call's arguments (its bare TypeError "incompatible function
// arguments") an `argument_error` (libwave.ArgumentTypeError) with the same message.
void add_text_signatures(pybind11::module_& m, PyObject* argument_error);

}  // namespace libwave_python
