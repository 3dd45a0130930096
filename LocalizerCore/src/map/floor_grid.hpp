// Geometry of a uniform square grid over one floor (map frame, meters). Cells are indexed row-major:
// index = iy * nx + ix, cell (ix, iy) covering [x0 + ix*cell, x0 + (ix+1)*cell) x [y0 + iy*cell, ...).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace wf::loc {

struct FloorGrid {
    /// South-west corner, meters.
    float x0 = 0, y0 = 0;
    /// Cell side, meters.
    float cell_m = 1;
    float inv_cell = 1;
    int32_t nx = 0, ny = 0;

    FloorGrid() = default;
    FloorGrid(float x0_, float y0_, float x1, float y1, float cell) : x0(x0_), y0(y0_), cell_m(cell) {
        inv_cell = 1.0f / cell;
        nx = static_cast<int32_t>(std::ceil((x1 - x0_) * inv_cell));
        ny = static_cast<int32_t>(std::ceil((y1 - y0_) * inv_cell));
        if (nx < 1) nx = 1;
        if (ny < 1) ny = 1;
    }

    int64_t cell_count() const { return static_cast<int64_t>(nx) * ny; }

    /// Cell index of a point, or -1 outside the grid (or non-finite).
    inline int32_t index(float x, float y) const {
        const float fx = (x - x0) * inv_cell;
        const float fy = (y - y0) * inv_cell;
        // The negated comparisons also reject NaN.
        if (!(fx >= 0.0f && fy >= 0.0f && fx < static_cast<float>(nx) && fy < static_cast<float>(ny))) return -1;
        return static_cast<int32_t>(fy) * nx + static_cast<int32_t>(fx);
    }
    /// Same as index() (the same float arithmetic, so the same cell), without branches so that loops over
    /// many points vectorise: -1 outside the grid or for a non-finite point.
    inline int32_t index_branch_free(float x, float y) const {
        const float fx = (x - x0) * inv_cell;
        const float fy = (y - y0) * inv_cell;
        const bool in = (fx >= 0.0f) & (fy >= 0.0f) & (fx < static_cast<float>(nx)) & (fy < static_cast<float>(ny));
        const float cx = in ? fx : 0.0f, cy = in ? fy : 0.0f;  // keeps the int conversion in range (no UB)
        const int32_t c = static_cast<int32_t>(cy) * nx + static_cast<int32_t>(cx);
        return in ? c : -1;
    }
    /// Column of x clamped into the grid. Truncation equals floor here: the only values where they differ
    /// are negative, and those clamp to 0 either way (and it avoids a libm call without SSE4.1).
    inline int32_t clamp_ix(float x) const { return clampi(to_int((x - x0) * inv_cell), nx); }
    inline int32_t clamp_iy(float y) const { return clampi(to_int((y - y0) * inv_cell), ny); }
    float center_x(int32_t ix) const { return x0 + (static_cast<float>(ix) + 0.5f) * cell_m; }
    float center_y(int32_t iy) const { return y0 + (static_cast<float>(iy) + 0.5f) * cell_m; }

private:
    static inline int32_t to_int(float v) {
        // Saturate before converting (NaN and huge values map to the low end, then clamp to 0).
        if (!(v > -1e9f)) return -1;
        if (v > 1e9f) return 1000000000;
        return static_cast<int32_t>(v);
    }
    static inline int32_t clampi(int32_t v, int32_t n) { return v < 0 ? 0 : (v >= n ? n - 1 : v); }
};

}  // namespace wf::loc
