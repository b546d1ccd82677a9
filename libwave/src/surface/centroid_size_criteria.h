// Mesh_2's size criterion with the target size read at each triangle's centroid, for
// the CGAL meshers of the water mesh and the sea skirt. Private to libwave (CGAL TUs).
#pragma once

#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/squared_distance_2.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace wave::detail {

/// A triangle whose longest edge exceeds the size at its centroid is split first
/// (imperatively bad), then the angle bound applies. `size(x, y)` returns the target
/// edge length there (m), or infinity for no size limit (shape only).
template <class CDT>
class CentroidSizeCriteria : public CGAL::Delaunay_mesh_size_criteria_2<CDT> {
    using Base = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
    using SizeAt = std::function<double(double, double)>;
    const SizeAt* size_;

public:
    /// `size` must outlive the criteria and the mesher.
    CentroidSizeCriteria(double squared_sine_bound, const SizeAt& size) : Base(squared_sine_bound, 0.0), size_(&size) {}

    class Is_bad : public Base::Is_bad {
        const SizeAt* size_;

    public:
        using Quality = typename Base::Quality;
        Is_bad(double bound, const typename Base::Geom_traits& geom, const SizeAt* size)
            : Base::Is_bad(bound, 0.0, geom), size_(size) {}

        CGAL::Mesh_2::Face_badness operator()(const Quality q) const { return Base::Is_bad::operator()(q); }

        CGAL::Mesh_2::Face_badness operator()(const typename CDT::Face_handle& fh, Quality& q) const {
            const CGAL::Mesh_2::Face_badness shape = Base::Is_bad::operator()(fh, q);  // q: (sine², 0)
            const auto &a = fh->vertex(0)->point(), &b = fh->vertex(1)->point(), &c = fh->vertex(2)->point();
            const double s = (*size_)((a.x() + b.x() + c.x()) / 3.0, (a.y() + b.y() + c.y()) / 3.0);
            const double longest = std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c), CGAL::squared_distance(c, a)});
            q.second = std::isfinite(s) ? longest / (s * s) : 0.0;
            return q.size() > 1.0 ? CGAL::Mesh_2::IMPERATIVELY_BAD : shape;
        }
    };

    Is_bad is_bad_object() const { return Is_bad(this->bound(), this->traits, size_); }
};

}  // namespace wave::detail
