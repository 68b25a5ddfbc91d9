// The one median every benchmark suite reports (empty: 0).
#pragma once

#include <algorithm>
#include <vector>

namespace qp::cli {

inline double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace qp::cli
