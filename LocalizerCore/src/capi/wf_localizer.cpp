// C ABI shell (include/wf_localizer.h): argument checks, exception firewall, per-handle last error.
// Every entry point catches everything: std::bad_alloc becomes WF_LOC_ERR_OUT_OF_MEMORY, anything else
// WF_LOC_ERR_INTERNAL with the message kept on the handle. wf_localizer_create has no handle to keep its
// message on when it fails: that message is kept per thread and read with wf_localizer_last_error(NULL).
#include "wf_localizer.h"

#include <algorithm>
#include <exception>
#include <memory>
#include <new>
#include <string>

#include "map/localizer_map.hpp"
#include "pf/particle_filter.hpp"

struct wf_localizer {
    std::unique_ptr<wf::loc::ParticleFilter> filter;
    std::string last_error;
};

namespace {

/// Why the calling thread's last wf_localizer_create failed ("" after a success).
thread_local std::string t_create_error;

int create_failed(int status, std::string message) {
    t_create_error = std::move(message);
    return status;
}

int record(wf_localizer *loc, int status) {
    if (loc) {
        loc->last_error = status == WF_LOC_OK ? std::string() : loc->filter->error();
        loc->filter->clear_error();
    }
    return status;
}

template <typename F>
int guarded(wf_localizer *loc, F &&body) {
    try {
        return record(loc, body());
    } catch (const std::bad_alloc &) {
        if (loc) loc->last_error = "out of memory";
        return WF_LOC_ERR_OUT_OF_MEMORY;
    } catch (const std::exception &e) {
        if (loc) loc->last_error = std::string("internal error: ") + e.what();
        return WF_LOC_ERR_INTERNAL;
    } catch (...) {
        if (loc) loc->last_error = "internal error: unknown exception";
        return WF_LOC_ERR_INTERNAL;
    }
}

}  // namespace

extern "C" {

int wf_localizer_options_init(wf_localizer_options *opts, unsigned int version) {
    if (!opts) return WF_LOC_ERR_INVALID_ARGUMENT;
    if (version != WF_LOCALIZER_OPTIONS_VERSION) return WF_LOC_ERR_VERSION;
    const wf_localizer_options defaults = WF_LOCALIZER_OPTIONS_INIT;
    *opts = defaults;
    return WF_LOC_OK;
}

int wf_localizer_create(wf_localizer **out, const wf_localizer_map *map, const wf_localizer_options *opts,
                        uint64_t seed) {
    try {
        t_create_error.clear();
        if (!out) return create_failed(WF_LOC_ERR_INVALID_ARGUMENT, "out (the handle's address) is NULL");
        *out = nullptr;
        if (!map) return create_failed(WF_LOC_ERR_INVALID_ARGUMENT, "map is NULL");
        wf_localizer_options o = WF_LOCALIZER_OPTIONS_INIT;
        if (opts) o = *opts;
        std::string error;
        int status = wf::loc::validate_options(o, error);
        if (status != WF_LOC_OK) return create_failed(status, "options: " + error);
        wf::loc::LocalizerMap lm;
        status = wf::loc::build_localizer_map(*map, o, lm, error);
        if (status != WF_LOC_OK) return create_failed(status, error);
        auto handle = std::make_unique<wf_localizer>();
        handle->filter = std::make_unique<wf::loc::ParticleFilter>(std::move(lm), o, seed);
        *out = handle.release();
        return WF_LOC_OK;
    } catch (const std::bad_alloc &) {
        return create_failed(WF_LOC_ERR_OUT_OF_MEMORY, "out of memory while building the map's grids");
    } catch (const std::exception &e) {
        return create_failed(WF_LOC_ERR_INTERNAL, std::string("internal error: ") + e.what());
    } catch (...) {
        return create_failed(WF_LOC_ERR_INTERNAL, "internal error: unknown exception");
    }
}

void wf_localizer_free(wf_localizer *loc) { delete loc; }

const char *wf_localizer_last_error(const wf_localizer *loc) {
    return loc ? loc->last_error.c_str() : t_create_error.c_str();
}

const char *wf_localizer_status_string(int status) {
    switch (status) {
        case WF_LOC_OK: return "ok";
        case WF_LOC_ERR_INVALID_ARGUMENT: return "invalid argument";
        case WF_LOC_ERR_OUT_OF_MEMORY: return "out of memory";
        case WF_LOC_ERR_VERSION: return "unsupported struct version";
        case WF_LOC_ERR_INVALID_MAP: return "invalid map";
        case WF_LOC_ERR_NO_WALKABLE_SPACE: return "no walkable space";
        case WF_LOC_ERR_NOT_INITIALIZED: return "filter not initialized";
        case WF_LOC_ERR_NON_FINITE_INPUT: return "non-finite input ignored";
        case WF_LOC_ERR_INTERNAL: return "internal error";
        default: return "unknown status";
    }
}

int wf_localizer_init_floor_only(wf_localizer *loc, int32_t floor_index) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->init_floor_only(floor_index); });
}

int wf_localizer_init_start_point(wf_localizer *loc, int32_t floor_index, double x, double y, double radius_m) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->init_start_point(floor_index, x, y, radius_m); });
}

int wf_localizer_set_compass_prior(wf_localizer *loc, double heading_in_map_rad, double sigma_rad) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->set_compass_prior(heading_in_map_rad, sigma_rad); });
}

int wf_localizer_predict(wf_localizer *loc, const wf_vio_sample *sample) {
    if (!loc || !sample) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->predict(*sample); });
}

int wf_localizer_note_vio_reset(wf_localizer *loc) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->note_vio_reset(); });
}

int wf_localizer_update_signs(wf_localizer *loc, const wf_sign_observation *observations, size_t count, double t) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->update_signs(observations, count, t); });
}

int wf_localizer_update_signs_searched(wf_localizer *loc, const wf_sign_observation *observations, size_t count,
                                       double t, const int32_t *unsearched_kinds, size_t unsearched_count) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] {
        return loc->filter->update_signs(observations, count, t, unsearched_kinds, unsearched_count);
    });
}

int wf_localizer_update_planes(wf_localizer *loc, const wf_plane_observation *planes, size_t count, double t) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->update_planes(planes, count, t); });
}

int wf_localizer_update_altitude(wf_localizer *loc, double relative_altitude_m, double t) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->update_altitude(relative_altitude_m, t); });
}

int wf_localizer_update_compass(wf_localizer *loc, double heading_in_map_rad, double accuracy_rad, double t) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] { return loc->filter->update_compass(heading_in_map_rad, accuracy_rad, t); });
}

int wf_localizer_set_parameter(wf_localizer *loc, const char *name, double value) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    if (!name) {
        loc->last_error = "parameter name is NULL";
        return WF_LOC_ERR_INVALID_ARGUMENT;
    }
    return guarded(loc, [&] { return loc->filter->set_parameter(name, value); });
}

int wf_localizer_get_parameter(wf_localizer *loc, const char *name, double *value) {
    if (!loc) return WF_LOC_ERR_INVALID_ARGUMENT;
    if (!name || !value) {
        loc->last_error = "parameter name or value pointer is NULL";
        return WF_LOC_ERR_INVALID_ARGUMENT;
    }
    return guarded(loc, [&] { return loc->filter->get_parameter(name, *value); });
}

int wf_localizer_get_estimate(wf_localizer *loc, wf_localizer_estimate *out) {
    if (!loc || !out) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] {
        *out = loc->filter->estimate();
        return static_cast<int>(WF_LOC_OK);
    });
}

int wf_localizer_get_hypotheses(wf_localizer *loc, wf_localizer_hypothesis *out, size_t capacity, size_t *count) {
    if (count) *count = 0;
    if (!loc || !count || (capacity > 0 && !out)) return WF_LOC_ERR_INVALID_ARGUMENT;
    return guarded(loc, [&] {
        loc->filter->estimate();
        const std::vector<wf_localizer_hypothesis> &h = loc->filter->hypotheses();
        const size_t m = std::min(h.size(), capacity);
        std::copy(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(m), out);
        *count = m;
        return static_cast<int>(WF_LOC_OK);
    });
}

int wf_localizer_get_floor_symmetries(const wf_localizer *loc, int32_t floor_index, wf_localizer_floor_symmetry *out,
                                      size_t capacity, size_t *count) {
    if (count) *count = 0;
    if (!loc || !count || (capacity > 0 && !out)) return WF_LOC_ERR_INVALID_ARGUMENT;
    const wf::loc::LocalizerMap &map = loc->filter->map();
    if (floor_index < 0 || static_cast<size_t>(floor_index) >= map.floors.size()) return WF_LOC_ERR_INVALID_ARGUMENT;
    const std::vector<wf::loc::FloorSymmetry> &s = map.floors[static_cast<size_t>(floor_index)].symmetries;
    const size_t m = std::min(s.size(), capacity);
    for (size_t k = 0; k < m; ++k) {
        out[k] = {s[k].angle_rad, s[k].cx, s[k].cy, s[k].matched_fraction};
    }
    *count = m;
    return WF_LOC_OK;
}

int wf_localizer_get_particles(const wf_localizer *loc, wf_localizer_particle *out, size_t capacity, size_t *count) {
    if (count) *count = 0;
    if (!loc || !count || (capacity > 0 && !out)) return WF_LOC_ERR_INVALID_ARGUMENT;
    try {
        const wf::loc::ParticleSet &p = loc->filter->particles();
        const size_t n = p.size();
        const size_t m = std::min(n, capacity);
        const float yaw = loc->filter->vio_yaw();
        for (size_t k = 0; k < m; ++k) {
            const size_t i = n > capacity ? (k * n) / m : k;  // even subsample
            wf_localizer_particle &q = out[k];
            q.x = p.x[i];
            q.y = p.y[i];
            float h = yaw + p.yaw_offset[i];
            h = std::remainder(h, 6.28318530717958647692f);
            q.heading_rad = h;
            q.scale = p.scale[i];
            q.weight = p.weight[i];
            q.floor_index = p.floor[i];
        }
        *count = m;
        return WF_LOC_OK;
    } catch (...) {
        return WF_LOC_ERR_INTERNAL;
    }
}

size_t wf_localizer_particle_count(const wf_localizer *loc) { return loc ? loc->filter->particles().size() : 0; }

}  // extern "C"
