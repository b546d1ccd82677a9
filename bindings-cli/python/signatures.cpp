// inspect.signature on pybind11 functions, and their argument refusals as libwave errors. pybind11 writes a function's typed signature
// as the first line of its docstring (`plan(scene: Scene, seafloor: Optional[Seafloor] =
// None) -> Plan`), which CPython does not read: a builtin's signature comes from a
// docstring that starts `name(params)\n--\n\n` (its __text_signature__), with
// parameters as Python source and no annotations. This prefixes each docstring with one
// made from pybind11's line; __doc__ (the text after the marker) stays as it was, so
// help() and scripts/python-stubs.py read the typed line as before.
#include "signatures.h"

#include <Python.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace libwave_python {
namespace {

namespace py = pybind11;

// `text` split at commas outside brackets and quotes, each part trimmed.
std::vector<std::string> split_top(const std::string& text) {
    std::vector<std::string> parts;
    std::string current;
    int depth = 0;
    char quote = 0;
    for (const char c : text) {
        if (quote) {
            if (c == quote) quote = 0;
        } else if (c == '\'' || c == '"') {
            quote = c;
        } else if (c == '[' || c == '(' || c == '{' || c == '<') {
            ++depth;
        } else if (c == ']' || c == ')' || c == '}' || c == '>') {
            --depth;
        } else if (c == ',' && depth == 0) {
            parts.push_back(current);
            current.clear();
            continue;
        }
        current += c;
    }
    parts.push_back(current);
    for (std::string& p : parts) {
        const auto first = p.find_first_not_of(' '), last = p.find_last_not_of(' ');
        p = first == std::string::npos ? std::string() : p.substr(first, last - first + 1);
    }
    return parts;
}

// Whether pybind11's repr of a default is a literal inspect can evaluate: numbers,
// strings, None, True, False, and tuples or lists of them — not an enum's
// `<PlanStages.all: 7>` or an object's repr (those are shown as `...`).
bool literal(const std::string& d) {
    if (d.empty()) return false;
    for (std::size_t i = 0; i < d.size();) {
        const char c = d[i];
        if (c == '\'' || c == '"') {
            const std::size_t end = d.find(c, i + 1);
            if (end == std::string::npos) return false;
            i = end + 1;
        } else if (std::isdigit(static_cast<unsigned char>(c))) {
            while (i < d.size() && (std::isalnum(static_cast<unsigned char>(d[i])) || d[i] == '.' ||
                                    ((d[i] == '-' || d[i] == '+') && (d[i - 1] == 'e' || d[i - 1] == 'E'))))
                ++i;
        } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
            std::size_t end = i;
            while (end < d.size() && (std::isalnum(static_cast<unsigned char>(d[end])) || d[end] == '_')) ++end;
            const std::string word = d.substr(i, end - i);
            if (word != "None" && word != "True" && word != "False") return false;
            i = end;
        } else if (std::strchr("[](), -+.", c)) {
            ++i;
        } else {
            return false;
        }
    }
    return true;
}

// `name(params)\n--\n\n` from pybind11's first docstring line, or "" if it has none.
std::string text_signature(const char* name, const char* doc) {
    const std::string line(doc, std::strcspn(doc, "\n"));
    const std::size_t n = std::strlen(name);
    if (line.compare(0, n, name) != 0 || line.size() <= n || line[n] != '(') return {};
    int depth = 0;
    char quote = 0;
    std::size_t close = std::string::npos;
    for (std::size_t i = n; i < line.size() && close == std::string::npos; ++i) {
        const char c = line[i];
        if (quote) {
            if (c == quote) quote = 0;
        } else if (c == '\'' || c == '"') {
            quote = c;
        } else if (c == '(' || c == '[' || c == '{') {
            ++depth;
        } else if (c == ')' || c == ']' || c == '}') {
            if (--depth == 0) close = i;
        }
    }
    if (close == std::string::npos) return {};
    std::string params;
    for (const std::string& part : split_top(line.substr(n + 1, close - n - 1))) {
        if (part.empty()) continue;
        std::string out;
        if (part == "*" || part == "/" || part[0] == '*') {
            out = part.substr(0, part.find(':'));
        } else {
            out = part.substr(0, part.find_first_of(":="));
            while (!out.empty() && out.back() == ' ') out.pop_back();
            // The default: after the first '=' outside brackets (pybind11 writes " = ").
            int level = 0;
            for (std::size_t i = 0; i < part.size(); ++i) {
                const char c = part[i];
                if (c == '[' || c == '(' || c == '<' || c == '{') ++level;
                if (c == ']' || c == ')' || c == '>' || c == '}') --level;
                if (c == '=' && level == 0) {
                    std::string d = part.substr(i + 1);
                    d.erase(0, d.find_first_not_of(' '));
                    out += "=" + (literal(d) ? d : std::string("..."));
                    break;
                }
            }
        }
        params += (params.empty() ? "" : ", ") + out;
    }
    return std::string(name) + "(" + params + ")\n--\n\n";
}

// pybind11's one dispatcher (every function's ml_meth) and the exception its refusals of
// arguments become (add_text_signatures).
PyCFunction pybind11_dispatcher = nullptr;
PyObject* argument_type_error = nullptr;

// Calls pybind11's dispatcher; its own refusal of the arguments (no overload takes them:
// a camera of 2 numbers, a str for a float, a negative count) — a bare TypeError — is
// raised as libwave.ArgumentTypeError (a libwave.Error that is also a TypeError) with the
// same message, which names the function, the types it takes and the ones given.
PyObject* dispatch(PyObject* self, PyObject* args, PyObject* kwargs) {
    PyObject* result = reinterpret_cast<PyCFunctionWithKeywords>(reinterpret_cast<void (*)()>(pybind11_dispatcher))(self, args, kwargs);
    if (result || !PyErr_ExceptionMatches(PyExc_TypeError)) return result;
    PyObject *type = nullptr, *value = nullptr, *traceback = nullptr;
    PyErr_Fetch(&type, &value, &traceback);
    const char* text = value && PyUnicode_Check(value) ? PyUnicode_AsUTF8(value) : nullptr;
    if (type == PyExc_TypeError && text &&
        (std::strstr(text, "(): incompatible function arguments") || std::strstr(text, "(): incompatible constructor arguments"))) {
        PyErr_SetString(argument_type_error, text);
        Py_XDECREF(type);
        Py_XDECREF(value);
        Py_XDECREF(traceback);
        return nullptr;
    }
    PyErr_Restore(type, value, traceback);
    return nullptr;
}

void sign(PyObject* function) {
    if (!function || !PyCFunction_Check(function)) return;
    PyMethodDef* def = reinterpret_cast<PyCFunctionObject*>(function)->m_ml;
    // pybind11's functions: its dispatcher, their record in a capsule as `self`.
    if (def && def->ml_flags == (METH_VARARGS | METH_KEYWORDS) && PyCapsule_CheckExact(PyCFunction_GET_SELF(function)) && def->ml_meth != reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&dispatch))) {
        if (!pybind11_dispatcher) pybind11_dispatcher = def->ml_meth;
        if (def->ml_meth == pybind11_dispatcher) def->ml_meth = reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&dispatch));
    }
    if (!def || !def->ml_doc || !def->ml_name || std::strstr(def->ml_doc, ")\n--\n\n")) return;
    const std::string prefix = text_signature(def->ml_name, def->ml_doc);
    if (prefix.empty()) return;
    // pybind11 allocated ml_doc with strdup and frees it with std::free.
    const std::string doc = prefix + def->ml_doc;
    char* copy = static_cast<char*>(std::malloc(doc.size() + 1));
    if (!copy) return;
    std::memcpy(copy, doc.c_str(), doc.size() + 1);
    std::free(const_cast<char*>(def->ml_doc));
    def->ml_doc = copy;
}

}  // namespace

void add_text_signatures(py::module_& m, PyObject* argument_error) {
    argument_type_error = argument_error;
    const py::object staticmethod = py::module_::import("builtins").attr("staticmethod");
    for (const auto& [key, value] : py::dict(m.attr("__dict__"))) {
        (void)key;
        if (PyCFunction_Check(value.ptr())) {
            sign(value.ptr());
        } else if (PyType_Check(value.ptr())) {
            for (const auto& [member, entry] : py::dict(value.attr("__dict__"))) {
                (void)member;
                if (PyInstanceMethod_Check(entry.ptr()))
                    sign(PyInstanceMethod_Function(entry.ptr()));
                else if (py::isinstance(entry, staticmethod))
                    sign(entry.attr("__func__").ptr());
            }
        }
    }
}

}  // namespace libwave_python
