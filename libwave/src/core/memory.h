// Internal: large buffers with transparent huge pages. On the virtual machines the
// pipeline runs on, the first touch of each 4 KiB page costs ~10 µs (2.5 ms a MB:
// a 1 M-vertex frame's arrays took longer to fault in than to compute); with 2 MiB
// pages the same first touch is ~0.1 ms a MB. Linux only; a no-op elsewhere.
#pragma once

#include <cstddef>
#include <vector>

namespace wave::detail {

/// Asks for transparent huge pages over the whole 2 MiB pages inside [p, p + bytes).
/// Call it before the memory is first touched (pages already faulted in stay small).
/// Regions under 4 MiB are left alone. Never fails: the kernel may decline.
void advise_huge_pages(void* p, std::size_t bytes) noexcept;

/// Makes `v` hold n elements whose values the caller is about to overwrite: when it
/// must grow, its old storage is dropped (not copied) and the new one advised for huge
/// pages before the value-initialising resize touches it. Elements it already held
/// (when it had the capacity) keep their values.
template <class T>
void size_for_overwrite(std::vector<T>& v, std::size_t n) {
    if (v.capacity() < n) {
        std::vector<T>().swap(v);
        v.reserve(n);
        advise_huge_pages(v.data(), n * sizeof(T));
    }
    v.resize(n);
}

}  // namespace wave::detail
