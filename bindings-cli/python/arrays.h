// NumPy arrays for the module's bindings (module.cpp, stages.cpp).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "libwave/errors.h"

#include <cstring>
#include <string>
#include <vector>

namespace libwave_python {

namespace py = pybind11;

// A read-only NumPy view of a std::vector owned by the Python object `owner` (kept
// alive by the array's base), shaped as given: libwave's buffers, no copy. Typed, so that
// signatures and stubs show its dtype.
template <class T>
py::array_t<T> view(const std::vector<T>& data, std::vector<py::ssize_t> shape, const py::object& owner) {
    std::vector<py::ssize_t> strides(shape.size());
    py::ssize_t step = sizeof(T);
    for (std::size_t i = shape.size(); i-- > 0;) {
        strides[i] = step;
        step *= shape[i];
    }
    if (data.empty()) return py::array_t<T>(shape);
    py::array_t<T> a(shape, strides, data.data(), owner);
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return a;
}

inline bool any_object(PyObject*) { return true; }

// An array argument read as numbers: any object is taken (to_vector converts it and
// refuses what is not numbers, naming the argument — never pybind11's own TypeError);
// signatures and stubs show numpy.typing.ArrayLike.
class ArrayLike : public py::object {
public:
    PYBIND11_OBJECT_DEFAULT(ArrayLike, py::object, any_object)
};

// A writable C-contiguous float32 array a function writes into (checked by the function,
// naming it); shown as numpy.typing.NDArray[numpy.float32].
class Float32Out : public py::object {
public:
    PYBIND11_OBJECT_DEFAULT(Float32Out, py::object, any_object)
};

// An argument of the wrong type or layout (not numbers, not a writable float32 array):
// raised in Python as libwave.ArgumentTypeError, an InputError (so a libwave.Error) that
// is also a TypeError. Wrong shapes and lengths are InputError (also a ValueError).
class ArgumentTypeError : public wave::InputError {
public:
    using wave::InputError::InputError;
};

// An array's shape as Python prints it: "(4, 2)".
inline std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// A vector from any array-like of numbers (converted to T, C order): flat, holding a
// multiple of `per_item` values, or (for per_item > 1) of shape (n, per_item); `what`
// names the argument in the error (ArgumentTypeError, InputError).
template <class T>
std::vector<T> to_vector(const py::handle& values, std::size_t per_item, const std::string& what) {
    const auto refuse = [&] {
        PyErr_Clear();
        throw ArgumentTypeError(what + ": expected an array of numbers, got " +
                                (py::isinstance<py::array>(values) ? "an array of " + std::string(py::str(py::array::ensure(values).dtype()))
                                                                   : std::string(py::str(py::type::of(values).attr("__name__")))));
    };
    const py::array given = py::array::ensure(values);  // any dtype (strings convert to numbers when forced: refused first)
    if (!given) refuse();
    const char kind = given.dtype().kind();
    if (kind == 'U' || kind == 'S' || kind == 'V' || kind == 'M' || kind == 'm') refuse();
    const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(given);
    if (!a) refuse();
    const std::size_t n = static_cast<std::size_t>(a.size());
    if (per_item > 1 && a.ndim() > 1 && (a.ndim() != 2 || static_cast<std::size_t>(a.shape(1)) != per_item))
        throw wave::InputError(what + ": expected shape (n, " + std::to_string(per_item) + ") or a flat array, got " + shape_text(a));
    if (per_item > 1 && n % per_item != 0)
        throw wave::InputError(what + ": expected " + std::to_string(per_item) + " values per item, got " + std::to_string(n) + " values");
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

namespace pybind11::detail {
template <>
struct handle_type_name<libwave_python::ArrayLike> {
    static constexpr auto name = const_name("numpy.typing.ArrayLike");
};
template <>
struct handle_type_name<libwave_python::Float32Out> {
    static constexpr auto name = const_name("numpy.typing.NDArray[numpy.float32]");
};
}  // namespace pybind11::detail
