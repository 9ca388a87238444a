// The C example's loop in C++: the header included from C++, the pipeline
// owned by a std::unique_ptr whose deleter frees it. `.ci/run` compiles it
// with the system's C++ compiler and compares its lines with the Rust
// program's.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "fieldguide.h"

namespace {
struct Free {
    void operator()(FgPipeline *p) const { fg_pipeline_free(p); }
};
}  // namespace

int main() {
    std::vector<FgPoint> waypoints;
    for (int i = 0; i <= 60; ++i) waypoints.push_back(FgPoint{static_cast<double>(i), 0.0});
    const FgConfig config{FG_PRESET_PATH_TRACKING, false, FgPose{1.2, 0.0, 0.0}, 1.0};
    FgPipeline *raw = nullptr;
    FgError error{};
    if (fg_pipeline_new(&config, waypoints.data(), waypoints.size(), &raw, &error) != FG_STATUS_OK) {
        std::fprintf(stderr, "refused: %s: %s\n", error.requirement, error.message);
        return 1;
    }
    std::unique_ptr<FgPipeline, Free> pipeline(raw);
    double x = 0.0, y = 0.5, heading = 0.0;
    const double dt = 0.01, wheelbase = 2.0;
    for (int k = 0; k <= 2000; ++k) {
        const FgTickInput input{nullptr, 0, true, FgPose{x, y, heading}, FgPose{x, y, heading}, 0.0, 0.0};
        FgTickOutput out{};
        if (fg_pipeline_step(pipeline.get(), &input, &out, &error) != FG_STATUS_OK) {
            std::fprintf(stderr, "tick %d refused: %s: %s\n", k, error.requirement, error.message);
            break;
        }
        if (k % 100 == 0) {
            std::printf("t=%.2f mode=%d command=%d speed=%.6f steering=%.6f y=%.6f\n", k * dt,
                        static_cast<int>(out.mode), out.has_command ? 1 : 0, out.speed_m_s,
                        out.steering_rad, out.lateral_error_m);
        }
        const double v = out.speed_m_s;
        x += dt * v * std::cos(heading);
        y += dt * v * std::sin(heading);
        heading += dt * v * std::tan(out.steering_rad) / wheelbase;
    }
    return 0;
}
