#include "map/floor_symmetry.hpp"

#include <algorithm>
#include <cmath>

namespace wf::loc {

std::vector<FloorSymmetry> find_floor_symmetries(const WallIndex &walls, const FloorSymmetryParams &params) {
    std::vector<FloorSymmetry> out;
    const size_t n = walls.segment_count();
    float x0, y0, x1, y1;
    if (!(params.sample_step_m > 0) || !walls.segment_bounds(x0, y0, x1, y1)) return out;
    double total_m = 0;
    for (size_t s = 0; s < n; ++s) {
        float ax, ay, bx, by;
        walls.segment(s, ax, ay, bx, by);
        total_m += std::hypot(bx - ax, by - ay);
    }
    if (!(total_m >= params.min_wall_length_m)) return out;
    const float cx = 0.5f * (x0 + x1), cy = 0.5f * (y0 + y1);
    constexpr double kQuarter = 1.5707963267948966;
    for (int quarter = 1; quarter <= 3; ++quarter) {
        FloorSymmetry sym;
        sym.angle_rad = static_cast<float>(quarter * kQuarter);
        sym.cx = cx;
        sym.cy = cy;
        // Exact cosines and sines of quarter turns (no 6e-8 residue tilting a 100 m floor by millimetres).
        sym.cos_a = quarter == 2 ? -1.0f : 0.0f;
        sym.sin_a = quarter == 1 ? 1.0f : (quarter == 3 ? -1.0f : 0.0f);
        // A quarter turn maps the bounding box onto itself only when it is square.
        if (quarter != 2 && std::fabs((x1 - x0) - (y1 - y0)) > 2 * params.tolerance_m) continue;
        double matched_m = 0;
        for (size_t s = 0; s < n; ++s) {
            float ax, ay, bx, by;
            walls.segment(s, ax, ay, bx, by);
            const double len = std::hypot(bx - ax, by - ay);
            const int steps = std::max(1, static_cast<int>(std::ceil(len / params.sample_step_m)));
            const double piece = len / steps;
            for (int k = 0; k < steps; ++k) {
                const float t = (static_cast<float>(k) + 0.5f) / static_cast<float>(steps);  // piece centres
                float rx, ry;
                sym.apply(ax + t * (bx - ax), ay + t * (by - ay), rx, ry);
                if (walls.distance_to_nearest(rx, ry, 2 * params.tolerance_m) <= params.tolerance_m) matched_m += piece;
            }
        }
        sym.matched_fraction = static_cast<float>(matched_m / total_m);
        if (sym.matched_fraction >= params.min_matched_fraction) out.push_back(sym);
    }
    return out;
}

}  // namespace wf::loc
