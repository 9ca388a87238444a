/* Bad input through fieldguide's C interface, as a C caller could send it:
 * null pointers, an invalid configuration, a path of one point, NaN in a
 * waypoint, in a pose and in the sideslip, a scan for a behaviour that is
 * not configured, too many scans, an infinite scan angle. Each must give
 * its status and an error naming a requirement; the pipeline must still
 * work after a refused tick. Exits non-zero at the first case that does
 * not. `.ci/run` compiles and runs it. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fieldguide.h"

static int failures = 0;

static void expect(const char *what, FgStatus got, FgStatus want, const FgError *error,
                   const char *requirement) {
    int ok = got == want;
    if (ok && requirement != NULL) {
        ok = strncmp(error->requirement, requirement, strlen(requirement)) == 0;
    }
    printf("%-44s status %d%s%s%s\n", what, (int)got, requirement ? " requirement " : "",
           requirement ? error->requirement : "", ok ? "" : "  <-- WRONG");
    if (!ok) failures += 1;
}

int main(void) {
    FgPoint path[41];
    for (int i = 0; i <= 40; ++i) {
        path[i].x = (double)i;
        path[i].y = 0.0;
    }
    FgConfig config = {FG_PRESET_FURROW, false, {1.2, 0.0, 0.0}, 1.0};
    FgPipeline *p = NULL;
    FgError error;

    expect("null configuration", fg_pipeline_new(NULL, path, 41, &p, &error),
           FG_STATUS_NULL_POINTER, &error, NULL);
    expect("null waypoints", fg_pipeline_new(&config, NULL, 41, &p, &error),
           FG_STATUS_NULL_POINTER, &error, NULL);
    expect("null result", fg_pipeline_new(&config, path, 41, NULL, &error),
           FG_STATUS_NULL_POINTER, &error, NULL);
    expect("one waypoint", fg_pipeline_new(&config, path, 1, &p, &error), FG_STATUS_REFUSED,
           &error, "PATH-");
    FgConfig bad = config;
    bad.smoothing_window_m = -1.0;
    expect("negative smoothing window", fg_pipeline_new(&bad, path, 41, &p, &error),
           FG_STATUS_REFUSED, &error, "");
    bad = config;
    bad.smoothing_window_m = NAN;
    expect("NaN smoothing window", fg_pipeline_new(&bad, path, 41, &p, &error),
           FG_STATUS_REFUSED, &error, "LIB-FINITE");
    bad = config;
    bad.preset = FG_PRESET_EDGE;
    bad.edge_lidar.heading = INFINITY;
    expect("infinite LiDAR mount", fg_pipeline_new(&bad, path, 41, &p, &error),
           FG_STATUS_REFUSED, &error, "LIB-FINITE");
    path[7].y = NAN;
    expect("NaN waypoint", fg_pipeline_new(&config, path, 41, &p, &error), FG_STATUS_REFUSED,
           &error, "LIB-FINITE");
    path[7].y = 0.0;

    expect("valid pipeline", fg_pipeline_new(&config, path, 41, &p, &error), FG_STATUS_OK,
           &error, NULL);
    FgTickInput in = {NULL, 0, true, {1.0, 0.2, 0.0}, {1.0, 0.2, 0.0}, 0.0, 0.0};
    FgTickOutput out;
    expect("null pipeline", fg_pipeline_step(NULL, &in, &out, &error), FG_STATUS_NULL_POINTER,
           &error, NULL);
    expect("null input", fg_pipeline_step(p, NULL, &out, &error), FG_STATUS_NULL_POINTER,
           &error, NULL);
    expect("null output", fg_pipeline_step(p, &in, NULL, &error), FG_STATUS_NULL_POINTER,
           &error, NULL);
    in.scan_count = 1;
    expect("one scan, null array", fg_pipeline_step(p, &in, &out, &error),
           FG_STATUS_NULL_POINTER, &error, NULL);
    in.scan_count = 0;
    in.gnss.y = NAN;
    expect("NaN GNSS pose", fg_pipeline_step(p, &in, &out, &error), FG_STATUS_REFUSED, &error,
           "LIB-FINITE");
    in.gnss.y = 0.2;
    in.sideslip_rear_rad = 2.0;
    expect("sideslip beyond pi/2", fg_pipeline_step(p, &in, &out, &error), FG_STATUS_REFUSED,
           &error, "");
    in.sideslip_rear_rad = 0.0;
    double ranges[360];
    for (int k = 0; k < 360; ++k) ranges[k] = (k % 7 == 0) ? NAN : 2.0;
    FgScan scans[5] = {
        {FG_BEHAVIOUR_EDGE, -3.14159, 0.0174533, ranges, 360, 0.05, 30.0},
        {FG_BEHAVIOUR_FURROW, -0.5, INFINITY, ranges, 360, 0.05, 30.0},
        {FG_BEHAVIOUR_FURROW, -0.5, 0.002, ranges, 360, 0.05, 30.0},
        {FG_BEHAVIOUR_FURROW, -0.5, 0.002, ranges, 360, 0.05, 30.0},
        {FG_BEHAVIOUR_FURROW, -0.5, 0.002, ranges, 360, 0.05, 30.0},
    };
    in.scans = scans;
    in.scan_count = 1;
    expect("scan for a behaviour not configured", fg_pipeline_step(p, &in, &out, &error),
           FG_STATUS_REFUSED, &error, "GD-INPUT");
    in.scans = &scans[1];
    expect("infinite scan increment", fg_pipeline_step(p, &in, &out, &error), FG_STATUS_REFUSED,
           &error, "LIB-FINITE");
    in.scans = &scans[2];
    in.scan_count = 3;
    expect("three scans for one behaviour", fg_pipeline_step(p, &in, &out, &error),
           FG_STATUS_REFUSED, &error, "GD-INPUT");
    in.scans = &scans[2];
    in.scan_count = 1;
    expect("a scan with NaN ranges, then a command", fg_pipeline_step(p, &in, &out, &error),
           FG_STATUS_OK, &error, NULL);
    if (!out.has_command || !(out.steering_rad < 0.0)) {
        printf("no command steering right from 0.2 m left of the path  <-- WRONG\n");
        failures += 1;
    }
    fg_pipeline_free(p);
    fg_pipeline_free(NULL);
    printf("%d wrong\n", failures);
    return failures == 0 ? 0 : 1;
}
