/* Path tracking through fieldguide's C interface: a straight 60 m path
 * recorded every metre, a bicycle with a 2 m wheelbase starting 0.5 m left
 * of it, 100 Hz for 20 s, one line a second. The same loop as
 * closed_loop.rs; `.ci/run` compiles this with the system's C compiler,
 * links it to the static library and compares its lines with the Rust
 * program's. */
#include <math.h>
#include <stdio.h>

#include "fieldguide.h"

int main(void) {
    FgPoint waypoints[61];
    for (int i = 0; i <= 60; ++i) {
        waypoints[i].x = (double)i;
        waypoints[i].y = 0.0;
    }
    FgConfig config = {FG_PRESET_PATH_TRACKING, false, {1.2, 0.0, 0.0}, 1.0};
    FgPipeline *pipeline = NULL;
    FgError error;
    FgStatus status = fg_pipeline_new(&config, waypoints, 61, &pipeline, &error);
    if (status != FG_STATUS_OK) {
        fprintf(stderr, "refused: %s: %s\n", error.requirement, error.message);
        return 1;
    }
    double x = 0.0, y = 0.5, heading = 0.0;
    const double dt = 0.01, wheelbase = 2.0;
    for (int k = 0; k <= 2000; ++k) {
        FgTickInput input = {NULL, 0, true, {x, y, heading}, {x, y, heading}, 0.0, 0.0};
        FgTickOutput out;
        status = fg_pipeline_step(pipeline, &input, &out, &error);
        if (status != FG_STATUS_OK) {
            fprintf(stderr, "tick %d refused: %s: %s\n", k, error.requirement, error.message);
            break;
        }
        if (k % 100 == 0) {
            printf("t=%.2f mode=%d command=%d speed=%.6f steering=%.6f y=%.6f\n", k * dt,
                   (int)out.mode, out.has_command ? 1 : 0, out.speed_m_s, out.steering_rad,
                   out.lateral_error_m);
        }
        double v = out.speed_m_s;
        x += dt * v * cos(heading);
        y += dt * v * sin(heading);
        heading += dt * v * tan(out.steering_rad) / wheelbase;
    }
    fg_pipeline_free(pipeline);
    return 0;
}
