// NumPy arrays for the module's bindings (module.cpp, stages.cpp).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstring>
#include <string>
#include <vector>

namespace libwave_python {

namespace py = pybind11;

// A read-only NumPy view of a std::vector owned by the Python object `owner` (kept
// alive by the array's base), shaped as given: libwave's buffers, no copy.
template <class T>
py::array view(const std::vector<T>& data, std::vector<py::ssize_t> shape, const py::object& owner) {
    std::vector<py::ssize_t> strides(shape.size());
    py::ssize_t step = sizeof(T);
    for (std::size_t i = shape.size(); i-- > 0;) {
        strides[i] = step;
        step *= shape[i];
    }
    if (data.empty()) return py::array_t<T>(shape);
    py::array a(py::dtype::of<T>(), shape, strides, data.data(), owner);
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return a;
}

// A vector from any array-like of numbers (converted to T, C order), checked to hold a
// multiple of `per_item` values; `what` names the argument in the error.
template <class T>
std::vector<T> to_vector(const py::handle& values, std::size_t per_item, const std::string& what) {
    const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(values);
    if (!a) throw py::type_error(what + ": expected an array of numbers");
    const std::size_t n = static_cast<std::size_t>(a.size());
    if (per_item > 1 && n % per_item != 0)
        throw py::value_error(what + ": expected " + std::to_string(per_item) + " values per item, got " +
                              std::to_string(n) + " values");
    std::vector<T> out(n);
    if (n > 0) std::memcpy(out.data(), a.data(), n * sizeof(T));
    return out;
}

// A new NumPy array holding a copy of `data`, shaped as given.
template <class T>
py::array_t<T> copy(const std::vector<T>& data, std::vector<py::ssize_t> shape) {
    py::array_t<T> out(shape);
    if (!data.empty()) std::memcpy(out.mutable_data(), data.data(), data.size() * sizeof(T));
    return out;
}

inline py::ssize_t ssize(std::size_t n) { return static_cast<py::ssize_t>(n); }

}  // namespace libwave_python
