/// \file
/// libwave — the one header of exception types (docs/conventions.md, errors).
///
/// Three layers of errors: InternalError for internal invariants (a libwave bug, never
/// the input's fault); the other exceptions for bad input at the API boundary (files,
/// scene values, out-of-range parameters) and the system; result flags for expected
/// physical outcomes (ray aground, caustic, total reflection).
/// Every message names the file / field / value and says what would be valid.
#pragma once

#include <stdexcept>
#include <string>

/// libwave's public API: flat structs of plain arrays and free functions, one header
/// per pipeline stage (see the file list); what is in wave::detail is internal.
namespace wave {

/// Base of every exception libwave throws on purpose.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Bad input: a file that cannot be read or parsed, a value out of range, an
/// inconsistent option. The CLI maps it to exit code 2.
class InputError : public Error {
public:
    using Error::Error;
};

/// A guard rail was hit (too many cells, rays, frames); the message names the limit
/// and the option that raises it. The CLI maps it to exit code 2.
class LimitError : public InputError {
public:
    using InputError::InputError;
};

/// Something failed that is not the input's fault (I/O error while writing, a
/// dependency failing). The CLI maps it to exit code 1.
class RuntimeError : public Error {
public:
    using Error::Error;
};

/// An internal invariant broke: a libwave bug, whatever the input (a model missing
/// from the registry, a lattice its planning should have kept in range). Never bad
/// input: the CLI maps it to exit code 1 and asks for a report.
class InternalError : public Error {
public:
    using Error::Error;
};

}  // namespace wave
