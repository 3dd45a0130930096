#include "pf/cluster_core.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"

namespace wf::loc {

namespace {

constexpr double kBinM = 0.05;
constexpr size_t kMaxBins = 4096;

/// Weighted median of one coordinate of the members, from a histogram over [lo, hi] (the bin's centre).
double weighted_median(const float *v, const float *w, const std::vector<uint32_t> &members, double lo, double hi,
                       std::vector<double> &hist) {
    const double span = std::max(hi - lo, 0.0);
    const size_t bins = std::min(kMaxBins, static_cast<size_t>(span / kBinM) + 1);
    const double width = std::max(kBinM, span / static_cast<double>(bins));
    hist.assign(bins, 0.0);
    double total = 0;
    for (uint32_t i : members) {
        const size_t b = std::min(bins - 1, static_cast<size_t>((v[i] - lo) / width));
        hist[b] += w[i];
        total += w[i];
    }
    double acc = 0;
    for (size_t b = 0; b < bins; ++b) {
        acc += hist[b];
        if (acc >= 0.5 * total) return lo + (static_cast<double>(b) + 0.5) * width;
    }
    return lo + 0.5 * span;
}

}  // namespace

double ClusterCore::position_std_m() const {
    // Largest eigenvalue of the 2 x 2 covariance in closed form.
    const double tr = 0.5 * (cov_xx + cov_yy), det = cov_xx * cov_yy - cov_xy * cov_xy;
    return std::sqrt(std::max(0.0, tr + std::sqrt(std::max(0.0, tr * tr - det))));
}

ClusterCore cluster_core(const ParticleSet &p, const std::vector<uint32_t> &members, double radius_m,
                         std::vector<double> &scratch) {
    ClusterCore c;
    if (members.empty()) return c;
    const float *px = p.x.data(), *py = p.y.data(), *pw = p.weight.data();
    double x0 = px[members[0]], x1 = x0, y0 = py[members[0]], y1 = y0;
    for (uint32_t i : members) {
        x0 = std::min<double>(x0, px[i]);
        x1 = std::max<double>(x1, px[i]);
        y0 = std::min<double>(y0, py[i]);
        y1 = std::max<double>(y1, py[i]);
    }
    const double mx_med = weighted_median(px, pw, members, x0, x1, scratch);
    const double my_med = weighted_median(py, pw, members, y0, y1, scratch);
    return cluster_core_around(p, members, mx_med, my_med, radius_m);
}

ClusterCore cluster_core_around(const ParticleSet &p, const std::vector<uint32_t> &members, double centre_x,
                                double centre_y, double radius_m) {
    ClusterCore c;
    c.centre_x = centre_x;
    c.centre_y = centre_y;
    const float *px = p.x.data(), *py = p.y.data(), *pw = p.weight.data();
    const double r2 = radius_m * radius_m;
    double w = 0, sx = 0, sy = 0, oc = 0, os = 0;
    for (uint32_t i : members) {
        const double dx = px[i] - centre_x, dy = py[i] - centre_y;
        if (dx * dx + dy * dy > r2) continue;
        const double wi = pw[i];
        float so, co;
        fast_sincos(p.yaw_offset[i], so, co);
        w += wi;
        sx += wi * px[i];
        sy += wi * py[i];
        oc += wi * co;
        os += wi * so;
        ++c.count;
    }
    if (!(w > 0)) {
        c.count = 0;
        return c;
    }
    c.weight = w;
    c.x = sx / w;
    c.y = sy / w;
    c.yaw_cos_sum = oc;
    c.yaw_sin_sum = os;
    for (uint32_t i : members) {
        const double dmx = px[i] - centre_x, dmy = py[i] - centre_y;
        if (dmx * dmx + dmy * dmy > r2) continue;
        const double wi = pw[i] / w, dx = px[i] - c.x, dy = py[i] - c.y;
        c.cov_xx += wi * dx * dx;
        c.cov_xy += wi * dx * dy;
        c.cov_yy += wi * dy * dy;
    }
    return c;
}

double sighted_members(const ParticleSet &p, const std::vector<uint32_t> &members, std::vector<uint32_t> &out) {
    const float *ps0 = p.bias_s0.data(), *pw = p.weight.data();
    out.clear();
    for (uint32_t i : members) {
        if (ps0[i] > 0.0f) out.push_back(i);
    }
    double total = 0;
    for (size_t i = 0; i < p.size(); ++i) total += ps0[i] > 0.0f ? static_cast<double>(pw[i]) : 0.0;
    return total;
}

void sighted_weight_per_cluster(const ParticleSet &p, const std::vector<int32_t> &cluster_of, size_t cluster_count,
                                std::vector<double> &out) {
    out.assign(cluster_count, 0.0);
    const float *ps0 = p.bias_s0.data(), *pw = p.weight.data();
    const size_t n = std::min(p.size(), cluster_of.size());
    for (size_t i = 0; i < n; ++i) {
        const int32_t c = cluster_of[i];
        if (c >= 0 && static_cast<size_t>(c) < cluster_count && ps0[i] > 0.0f) out[static_cast<size_t>(c)] += pw[i];
    }
}

}  // namespace wf::loc
