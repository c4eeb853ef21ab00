/*
 * The per-object cost of one frame's selection through the C interface.
 *
 *   cargo build --release -p acuity-capi
 *   cc -O2 -I capi/include examples/c/bench.c \
 *      target/release/libacuity_capi.a -lpthread -ldl -lm -o bench
 *   ./bench --bench 50 [--objects 100000] [profile.acp ...]
 *
 * The scene of benches/select.rs: objects around the camera, most in
 * front (directions within +-1.2 x +-0.8 of -Z, distances log-uniform
 * from 2 to 500, radii 0.3 to 2), profiles given round-robin (the small
 * demo profile when none is given), on the calling thread, no change
 * list; every cycle selects the same 8 frames (the camera turns by 0.002
 * rad and moves 0.05 units a step, 4 steps out and back; an eye tracker's
 * gaze 5 deg right and 2 deg down, 90 Hz). The generator is splitmix64,
 * so capi/tests/bench.rs builds the same scene in Rust and compares.
 * Prints the median and the fastest cycle's time per object and frame.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "acuity.h"

static const char DEMO_PROFILE_JSON[] =
    "{\"format_version\": 3, \"name\": \"rock\","
    " \"lod_triangles\": [4000, 1000, 250, 60], \"bounding_radius\": 1.0,"
    " \"viewpoints\": [[0.0, 0.0, 1.0]], \"rung_diameters_px\": [256.0],"
    " \"transitions\": ["
    "  {\"feature_count\": 1, \"features\": [{\"freq_cdiam\": 200.0, \"area_diam2\": 0.01,"
    "    \"luminance\": [0.2, 0.5], \"masker\": [0.2, 0.5], \"count\": 1}]},"
    "  {\"feature_count\": 1, \"features\": [{\"freq_cdiam\": 100.0, \"area_diam2\": 0.01,"
    "    \"luminance\": [0.2, 0.5], \"masker\": [0.2, 0.5], \"count\": 1}]},"
    "  {\"feature_count\": 1, \"features\": [{\"freq_cdiam\": 50.0, \"area_diam2\": 0.01,"
    "    \"luminance\": [0.2, 0.5], \"masker\": [0.2, 0.5], \"count\": 1}]}],"
    " \"settings\": {}, \"inputs\": []}";

#define POSES 8
#define PI 3.14159265358979323846
#define CHECK(call)                                                            \
    do {                                                                       \
        AcuityStatus status_ = (call);                                         \
        if (status_ != ACUITY_OK) {                                            \
            fprintf(stderr, "error: %s (status %d)\n", acuity_last_error(),    \
                    (int)status_);                                             \
            return 1;                                                          \
        }                                                                      \
    } while (0)

static uint64_t rng_state;

/* splitmix64, uniform in [0, 1) with 53 bits. */
static double unit(void) {
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static double range(double lo, double hi) { return lo + (hi - lo) * unit(); }

static double now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e9 + (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    long cycles = 20, objects = 100000;
    const char *paths[64];
    int profile_count = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--bench") && i + 1 < argc)
            cycles = atol(argv[++i]);
        else if (!strcmp(argv[i], "--objects") && i + 1 < argc)
            objects = atol(argv[++i]);
        else if (argv[i][0] != '-' && profile_count < 64)
            paths[profile_count++] = argv[i];
        else {
            fprintf(stderr, "usage: %s [--bench CYCLES] [--objects N] [profile ...]\n", argv[0]);
            return 2;
        }
    }
    if (cycles < 1 || objects < 1) {
        fprintf(stderr, "error: --bench and --objects take a count >= 1\n");
        return 2;
    }

    AcuityDisplay display = {1920, 1080, 90.0f, 58.7f};
    AcuitySelector *selector;
    CHECK(acuity_selector_new(&display, NULL, &selector));
    uint32_t profiles[64];
    int n_profiles = profile_count > 0 ? profile_count : 1;
    for (int p = 0; p < n_profiles; p++) {
        AcuityProfile *profile;
        if (profile_count > 0)
            CHECK(acuity_profile_load(paths[p], &profile));
        else
            CHECK(acuity_profile_from_bytes((const uint8_t *)DEMO_PROFILE_JSON,
                                            strlen(DEMO_PROFILE_JSON), &profile));
        CHECK(acuity_selector_add_profile(selector, profile, &profiles[p]));
        CHECK(acuity_profile_free(profile));
    }

    rng_state = 42;
    for (long i = 0; i < objects; i++) {
        double dx = range(-1.2, 1.2), dy = range(-0.8, 0.8), dz = -1.0;
        double len = sqrt(dx * dx + dy * dy + dz * dz);
        double distance = exp(range(log(2.0), log(500.0)));
        double angle = range(0.0, 2.0 * PI);
        AcuityObjectDesc desc = {
            .center = {dx / len * distance, dy / len * distance, dz / len * distance},
            .rotation = {0.0f, (float)sin(0.5 * angle), 0.0f, (float)cos(0.5 * angle)},
            .radius = (float)range(0.3, 2.0),
            .profile = profiles[i % n_profiles],
        };
        AcuityObject handle;
        CHECK(acuity_selector_add_object(selector, &desc, &handle));
    }

    AcuityFrame frames[POSES];
    static const int steps[POSES] = {0, 1, 2, 3, 4, 3, 2, 1};
    double gx = tan(5.0 * PI / 180.0), gy = tan(-2.0 * PI / 180.0);
    double glen = sqrt(gx * gx + gy * gy + 1.0);
    for (int k = 0; k < POSES; k++) {
        CHECK(acuity_frame_default(&frames[k]));
        double half = 0.5 * 0.002 * steps[k];
        frames[k].camera_position = (AcuityVec3d){0.0, 0.0, -0.05 * steps[k]};
        frames[k].camera_orientation = (AcuityQuat){0.0f, (float)sin(half), 0.0f, (float)cos(half)};
        frames[k].gaze_direction = (AcuityVec3f){(float)(gx / glen), (float)(gy / glen), (float)(-1.0 / glen)};
        frames[k].tracker = ACUITY_TRACKER_EYE;
        frames[k].tracker_error_deg = 1.0f;
        frames[k].dt_s = 1.0f / 90.0f;
    }

    /* One cycle to warm up, counting what it draws. */
    uint64_t triangles = 0, visible = 0;
    for (int k = 0; k < POSES; k++) {
        AcuityStats stats;
        CHECK(acuity_selector_select(selector, &frames[k]));
        CHECK(acuity_selector_stats(selector, &stats));
        triangles += stats.triangles;
        visible += stats.visible;
    }
    double *ns = malloc((size_t)cycles * sizeof *ns);
    if (!ns)
        return 1;
    for (long c = 0; c < cycles; c++) {
        double start = now_ns();
        for (int k = 0; k < POSES; k++)
            CHECK(acuity_selector_select(selector, &frames[k]));
        ns[c] = (now_ns() - start) / ((double)POSES * (double)objects);
    }
    qsort(ns, (size_t)cycles, sizeof *ns, cmp_double);
    printf("C API: %ld objects, %d profiles, %ld cycles of %d frames: "
           "median %.2f ns/object, min %.2f ns/object, visible fraction %.3f, "
           "triangles %llu\n",
           objects, n_profiles, cycles, POSES, ns[cycles / 2], ns[0],
           (double)visible / ((double)POSES * (double)objects),
           (unsigned long long)triangles);
    free(ns);
    CHECK(acuity_selector_free(selector));
    return 0;
}
