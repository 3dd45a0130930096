// Helpers shared by the particle-filter tests: building the internal map and a zero-noise options set.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "map/localizer_map.hpp"
#include "support/synthetic_world.hpp"
#include "wf_localizer.h"

namespace wf::test {

inline wf_localizer_options default_options() {
    wf_localizer_options o;
    wf_localizer_options_init(&o, WF_LOCALIZER_OPTIONS_VERSION);
    return o;
}

inline wf::loc::LocalizerMap build_map(World &w, const wf_localizer_options &o) {
    wf::loc::LocalizerMap m;
    std::string err;
    EXPECT_EQ(wf::loc::build_localizer_map(w.map(), o, m, err), WF_LOC_OK) << err;
    return m;
}

}  // namespace wf::test
