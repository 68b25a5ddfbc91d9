// Evaluating a bicubic Bézier patch (core/culling/patch_culling.h's BicubicPoints, row-major, u along a
// row) in the tests: position and first derivatives, in float or in double.
#pragma once

#include <glm/vec3.hpp>

#include "culling/patch_culling.h"

namespace qp::test {

// Vec: glm::vec3 or glm::dvec3 (double keeps huge coordinates exact enough).
template <class Vec>
Vec bicubicBezierAt(const BicubicPoints& p, typename Vec::value_type u, typename Vec::value_type v, Vec* du = nullptr,
                    Vec* dv = nullptr) {
    using T = typename Vec::value_type;
    auto bern = [](T t, T* b, T* d) {
        const T s = T(1) - t;
        b[0] = s * s * s, b[1] = 3 * t * s * s, b[2] = 3 * t * t * s, b[3] = t * t * t;
        d[0] = -3 * s * s, d[1] = 3 * s * s - 6 * t * s, d[2] = 6 * t * s - 3 * t * t, d[3] = 3 * t * t;
    };
    T bu[4], bdu[4], bv[4], bdv[4];
    bern(u, bu, bdu);
    bern(v, bv, bdv);
    Vec out(0), ou(0), ov(0);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            const Vec q(p[4 * r + c]);
            out += bu[c] * bv[r] * q, ou += bdu[c] * bv[r] * q, ov += bu[c] * bdv[r] * q;
        }
    if (du) *du = ou;
    if (dv) *dv = ov;
    return out;
}

}  // namespace qp::test
