// Text signatures for inspect.signature (signatures.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace libwave_python {

// Gives every function and method of `m` (and of its classes) a text signature that
// inspect.signature reads — parameter names, kinds and defaults, from pybind11's own
// first docstring line — keeping that typed line and the docstring as __doc__.
void add_text_signatures(pybind11::module_& m);

}  // namespace libwave_python
