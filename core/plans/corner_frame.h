// The frame of a quad whose origin is its corner `rotation` (0..3, in winding order; u towards
// the next corner): where a point (u, v) of the quad's own frame lies in it, and what
// derivatives taken in it are in the quad's frame. A plan is evaluated in the frame of its start
// corner (face_config.h: `rotation`), a Stam patch in that of its extraordinary corner.
#pragma once

#include <cstdint>

namespace qp {

template <class Real>
void toCornerFrame(uint32_t rotation, Real u, Real v, Real& x, Real& y) {
    switch (rotation) {
    case 1: x = v; y = Real(1) - u; break;
    case 2: x = Real(1) - u; y = Real(1) - v; break;
    case 3: x = Real(1) - v; y = u; break;
    default: x = u; y = v; break;
    }
}

template <class Vec>
void derivativesToFaceFrame(uint32_t rotation, Vec& du, Vec& dv) {
    const Vec a = du, b = dv;
    switch (rotation) {
    case 1: du = -b; dv = a; break;
    case 2: du = -a; dv = -b; break;
    case 3: du = b; dv = -a; break;
    default: break;
    }
}

}  // namespace qp
