#include "map/floor_footprint.hpp"

#include <algorithm>
#include <cmath>

namespace wf::loc {

namespace {

struct Point {
    double x, y;
    bool operator<(const Point &o) const { return x < o.x || (x == o.x && y < o.y); }
    bool operator==(const Point &o) const { return x == o.x && y == o.y; }
};

double cross(const Point &o, const Point &a, const Point &b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/// Convex hull, counter-clockwise, without collinear points (Andrew's monotone chain).
std::vector<Point> convex_hull(std::vector<Point> pts) {
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 3) return pts;
    std::vector<Point> hull(2 * pts.size());
    size_t k = 0;
    for (const Point &p : pts) {  // lower chain
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
        hull[k++] = p;
    }
    const size_t lower = k + 1;
    for (size_t i = pts.size() - 1; i-- > 0;) {  // upper chain
        while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
        hull[k++] = pts[i];
    }
    hull.resize(k - 1);  // the last point is the first
    return hull;
}

}  // namespace

std::vector<float> floor_footprint_boundary(const float *walls, size_t wall_count, const float *points,
                                            size_t point_count, float margin_m) {
    std::vector<float> out;
    if (wall_count == 0 || !(margin_m > 0) || !std::isfinite(margin_m)) return out;
    // Octagon vertices at radius margin / cos(pi / 8): the octagon contains the disc of radius margin.
    constexpr int kSides = 8;
    constexpr double kPi = 3.14159265358979323846;
    const double r = static_cast<double>(margin_m) / std::cos(kPi / kSides);
    double ox[kSides], oy[kSides];
    for (int k = 0; k < kSides; ++k) {
        ox[k] = r * std::cos(2 * kPi * k / kSides);
        oy[k] = r * std::sin(2 * kPi * k / kSides);
    }
    std::vector<Point> pts;
    pts.reserve((2 * wall_count + point_count) * kSides);
    const auto grow = [&](float x, float y) {
        if (!std::isfinite(x) || !std::isfinite(y)) return;
        for (int k = 0; k < kSides; ++k) pts.push_back({x + ox[k], y + oy[k]});
    };
    for (size_t s = 0; s < wall_count; ++s) {
        grow(walls[4 * s], walls[4 * s + 1]);
        grow(walls[4 * s + 2], walls[4 * s + 3]);
    }
    for (size_t i = 0; i < point_count; ++i) grow(points[2 * i], points[2 * i + 1]);
    const std::vector<Point> hull = convex_hull(std::move(pts));
    if (hull.size() < 3) return out;
    out.reserve(4 * hull.size());
    for (size_t i = 0; i < hull.size(); ++i) {
        const Point &a = hull[i], &b = hull[(i + 1) % hull.size()];
        out.insert(out.end(), {static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(b.x),
                               static_cast<float>(b.y)});
    }
    return out;
}

}  // namespace wf::loc
