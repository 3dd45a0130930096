// Test fixtures for the particle filter: small synthetic buildings built with named builders, and a walk
// generator producing VIO samples and sign sightings with known truth. Geometry here is computed by brute
// force (no grids) so it checks the filter's precomputed structures independently.
#pragma once

#include <array>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "wf_localizer.h"

namespace wf::test {

constexpr double kPi = 3.14159265358979323846;
constexpr int32_t kExit = 0;
constexpr int32_t kRestroom = 1;

inline double wrap(double a) {
    a = std::fmod(a + kPi, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    return a - kPi;
}

struct SignSpec {
    int32_t kind;
    float x, y, facing_x, facing_y;
    bool double_sided = false;
    /// The sign's own recognition limits (wf_localizer_sign), 0 = the options'.
    float max_range_m = 0, max_view_angle_rad = 0;
};

struct FloorSpec {
    double elevation_m = 0;
    std::vector<std::array<float, 4>> walls;
    std::vector<SignSpec> signs;
    std::vector<std::array<float, 2>> links;
    std::vector<std::array<float, 2>> seeds;

    FloorSpec &wall(float ax, float ay, float bx, float by) { walls.push_back({ax, ay, bx, by}); return *this; }
    /// Closed polyline through the points.
    FloorSpec &polygon(const std::vector<std::array<float, 2>> &pts) {
        for (size_t i = 0; i < pts.size(); ++i) {
            const auto &a = pts[i];
            const auto &b = pts[(i + 1) % pts.size()];
            wall(a[0], a[1], b[0], b[1]);
        }
        return *this;
    }
    FloorSpec &box(float x0, float y0, float x1, float y1) { return polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}); }
    FloorSpec &sign(int32_t kind, float x, float y, float fx, float fy, bool both = false) {
        signs.push_back({kind, x, y, fx, fy, both});
        return *this;
    }
    FloorSpec &seed(float x, float y) { seeds.push_back({x, y}); return *this; }
    FloorSpec &link(float x, float y) { links.push_back({x, y}); return *this; }
};

/// A building and the C map struct pointing into its storage (valid while the World lives, unmoved).
struct World {
    std::vector<FloorSpec> floors;
    int32_t kind_count = 2;

    const wf_localizer_map &map() {
        c_signs_.clear();
        c_floors_.clear();
        c_signs_.resize(floors.size());
        for (size_t f = 0; f < floors.size(); ++f) {
            for (const SignSpec &s : floors[f].signs) {
                c_signs_[f].push_back({s.kind, s.x, s.y, s.facing_x, s.facing_y, s.double_sided ? 1 : 0, s.max_range_m,
                                       s.max_view_angle_rad});
            }
        }
        for (size_t f = 0; f < floors.size(); ++f) {
            const FloorSpec &fs = floors[f];
            wf_localizer_floor c{};
            c.elevation_m = fs.elevation_m;
            c.walls = fs.walls.empty() ? nullptr : fs.walls.front().data();
            c.wall_count = fs.walls.size();
            c.signs = c_signs_[f].empty() ? nullptr : c_signs_[f].data();
            c.sign_count = c_signs_[f].size();
            c.link_points = fs.links.empty() ? nullptr : fs.links.front().data();
            c.link_point_count = fs.links.size();
            c.seed_points = fs.seeds.empty() ? nullptr : fs.seeds.front().data();
            c.seed_point_count = fs.seeds.size();
            c_floors_.push_back(c);
        }
        c_map_.version = WF_LOCALIZER_MAP_VERSION;
        c_map_.floors = c_floors_.data();
        c_map_.floor_count = c_floors_.size();
        c_map_.kind_count = kind_count;
        return c_map_;
    }

private:
    std::vector<std::vector<wf_localizer_sign>> c_signs_;
    std::vector<wf_localizer_floor> c_floors_;
    wf_localizer_map c_map_{};
};

/// Straight corridor 20 m x 2 m, exit signs at both ends and one on the north wall.
inline World corridor_world() {
    World w;
    FloorSpec f;
    f.box(0, 0, 20, 2).seed(1, 1).seed(10, 1).seed(19, 1);
    f.sign(kExit, 20, 1, -1, 0).sign(kExit, 0, 1, 1, 0).sign(kExit, 8, 2, 0, -1);
    w.floors.push_back(f);
    return w;
}

/// L-shaped corridor: 30 m east-west (2.5 m wide) meeting a 25 m north-south corridor at its east end.
/// Signs are placed asymmetrically, so the pose is identifiable after a short walk.
inline World l_world() {
    World w;
    FloorSpec f;
    f.polygon({{0, 0}, {30, 0}, {30, 25}, {27.5f, 25}, {27.5f, 2.5f}, {0, 2.5f}});
    for (float x = 1; x < 29; x += 3) f.seed(x, 1.25f);
    for (float y = 4; y < 25; y += 3) f.seed(28.75f, y);
    f.sign(kExit, 0, 1.25f, 1, 0)          // west end wall, facing east
        .sign(kExit, 12, 2.5f, 0, -1)      // north wall, facing south
        .sign(kExit, 20, 0, 0, 1)          // south wall, facing north
        .sign(kExit, 30, 12, -1, 0)        // east wall of the north corridor, facing west
        .sign(kExit, 28.75f, 25, 0, -1)    // north end wall, facing south
        .sign(kExit, 27.5f, 18, 1, 0)      // west wall of the north corridor, facing east
        .sign(kRestroom, 6, 0, 0, 1);      // a restroom sign on the south wall
    w.floors.push_back(f);
    return w;
}

/// Corridor 30 m x 2 m, point-symmetric about its centre (15, 1): every sign has a twin rotated by 180
/// degrees, so a walker and its mirror image see exactly the same sightings.
inline World symmetric_world() {
    World w;
    FloorSpec f;
    f.box(0, 0, 30, 2);
    for (float x = 1; x < 30; x += 2) f.seed(x, 1);
    f.sign(kExit, 0, 1, 1, 0).sign(kExit, 30, 1, -1, 0).sign(kExit, 10, 2, 0, -1).sign(kExit, 20, 0, 0, 1);
    w.floors.push_back(f);
    return w;
}

/// Brute-force segment intersection (touching counts), independent of the library's.
inline bool brute_crosses(const std::vector<std::array<float, 4>> &walls, double px, double py, double qx, double qy) {
    for (const auto &w : walls) {
        const double ax = w[0], ay = w[1], bx = w[2], by = w[3];
        const double d1 = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
        const double d2 = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
        const double d3 = (qx - px) * (ay - py) - (qy - py) * (ax - px);
        const double d4 = (qx - px) * (by - py) - (qy - py) * (bx - px);
        if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0) || d1 == 0 || d2 == 0) &&
            ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0) || d3 == 0 || d4 == 0) && !(d1 == 0 && d2 == 0) &&
            !(d3 == 0 && d4 == 0)) {
            return true;
        }
    }
    return false;
}

struct WalkFrame {
    wf_vio_sample vio;
    std::vector<wf_sign_observation> sightings;
    double true_x, true_y, true_heading;
};

struct WalkParams {
    double rate_hz = 10;
    double speed_mps = 1.2;
    double turn_rate_radps = 1.5;
    /// VIO frame relative to the map: map = scale * Rot(yaw) * vio + origin.
    double vio_yaw_rad = 0.7;
    double vio_scale = 1.03;
    double vio_origin_x = -3, vio_origin_y = 5;
    /// Sightings.
    double fov_rad = 0.8 * 48 * kPi / 180;
    double max_range_m = 10;
    double detect_prob = 0.9;
    double range_sigma_frac = 0.08;
    /// Systematic relative range error of the detector: measured = true * (1 + bias) * (1 + noise).
    double range_bias_frac = 0.0;
    double bearing_sigma_rad = 2 * kPi / 180;
    double false_positive_prob = 0.0;
    double vio_step_noise = 0.01;
    uint64_t seed = 7;
};

/// Walks the waypoints (turning in place, then walking straight) and returns one frame per sample.
inline std::vector<WalkFrame> make_walk(const FloorSpec &floor, const std::vector<std::array<double, 2>> &waypoints,
                                        double initial_heading, const WalkParams &wp, double t0 = 0) {
    std::mt19937_64 gen(wp.seed);
    std::normal_distribution<double> n01(0, 1);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<WalkFrame> frames;
    const double dt = 1.0 / wp.rate_hz;
    double x = waypoints.front()[0], y = waypoints.front()[1], h = initial_heading;
    double t = t0;
    double vio_e = 0, vio_n = 0;  // integrated VIO (with its own small noise)
    bool first = true;
    double last_x = x, last_y = y;
    auto emit = [&]() {
        WalkFrame fr;
        if (first) {
            // VIO position of the start: vio = Rot(-yaw)(map - origin) / scale.
            const double mx = x - wp.vio_origin_x, my = y - wp.vio_origin_y;
            const double c = std::cos(-wp.vio_yaw_rad), s = std::sin(-wp.vio_yaw_rad);
            vio_e = (c * mx - s * my) / wp.vio_scale;
            vio_n = (s * mx + c * my) / wp.vio_scale;
            first = false;
        } else {
            const double mx = x - last_x, my = y - last_y;
            const double c = std::cos(-wp.vio_yaw_rad), s = std::sin(-wp.vio_yaw_rad);
            const double step = std::hypot(mx, my);
            vio_e += (c * mx - s * my) / wp.vio_scale + wp.vio_step_noise * step * n01(gen);
            vio_n += (s * mx + c * my) / wp.vio_scale + wp.vio_step_noise * step * n01(gen);
        }
        last_x = x;
        last_y = y;
        fr.vio = {t, vio_e, vio_n, wrap(h - wp.vio_yaw_rad), WF_VIO_TRACKING_NORMAL};
        fr.true_x = x;
        fr.true_y = y;
        fr.true_heading = h;
        for (const SignSpec &s : floor.signs) {
            const double dx = s.x - x, dy = s.y - y;
            const double r = std::hypot(dx, dy);
            if (r < 0.5 || r > wp.max_range_m) continue;
            if (!s.double_sided && s.facing_x * (x - s.x) + s.facing_y * (y - s.y) <= 0) continue;
            const double b = wrap(std::atan2(dy, dx) - h);
            if (std::fabs(b) > 0.5 * wp.fov_rad) continue;
            const double side = (s.facing_x * (x - s.x) + s.facing_y * (y - s.y)) >= 0 ? 1 : -1;
            const double tx = s.x + side * 0.05 * s.facing_x, ty = s.y + side * 0.05 * s.facing_y;
            if (brute_crosses(floor.walls, x, y, x + 0.99 * (tx - x), y + 0.99 * (ty - y))) continue;
            if (u01(gen) > wp.detect_prob) continue;
            fr.sightings.push_back({s.kind, r * (1 + wp.range_bias_frac) * (1 + wp.range_sigma_frac * n01(gen)),
                                    wrap(b + wp.bearing_sigma_rad * n01(gen)), 0.95});
        }
        if (u01(gen) < wp.false_positive_prob) {
            fr.sightings.push_back({kExit, 1 + 9 * u01(gen), (u01(gen) - 0.5) * wp.fov_rad, 0.9});
        }
        frames.push_back(fr);
        t += dt;
    };
    emit();
    for (size_t k = 1; k < waypoints.size(); ++k) {
        const double tx = waypoints[k][0], ty = waypoints[k][1];
        const double target = std::atan2(ty - y, tx - x);
        // Turn in place.
        for (;;) {
            const double e = wrap(target - h);
            const double step = wp.turn_rate_radps * dt;
            if (std::fabs(e) <= step) {
                h = target;
                break;
            }
            h = wrap(h + (e > 0 ? step : -step));
            emit();
        }
        const double len = std::hypot(tx - x, ty - y);
        const int steps = std::max(1, static_cast<int>(std::ceil(len / (wp.speed_mps * dt))));
        const double sx = x, sy = y;
        for (int i = 1; i <= steps; ++i) {
            x = sx + (tx - sx) * i / steps;
            y = sy + (ty - sy) * i / steps;
            emit();
        }
    }
    return frames;
}

}  // namespace wf::test
