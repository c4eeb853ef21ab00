/*
 * Embedding acuity from C: a profile, objects, a selection per frame, and
 * the list of objects whose LOD changed, which is what a renderer acts on.
 * The C twin of examples/minimal.rs (same scene, same frames, same lines).
 *
 *   cargo build --release -p acuity-capi
 *   cc -O2 -I capi/include examples/c/minimal.c \
 *      target/release/libacuity_capi.a -lpthread -ldl -lm -o minimal
 *   ./minimal            # the small profile below
 *   ./minimal rock.acp   # a profile written by `acuity preprocess`
 *
 * capi/tests/c_example.rs builds and runs it and checks its output against
 * the same scene selected in Rust.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "acuity.h"

/* A stand-in for a profile from `acuity preprocess` (examples/common's
 * demo_profile, as JSON): 4 LODs of 4000 to 60 triangles, one viewpoint,
 * one size rung, each transition removing one feature of half the
 * frequency of the one before. */
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

/* Every call returns a status; on failure, print the thread's last error
 * and leave through `fail` (which frees what was made). */
#define CHECK(call)                                                            \
    do {                                                                       \
        AcuityStatus status_ = (call);                                         \
        if (status_ != ACUITY_OK) {                                            \
            fprintf(stderr, "error: %s (status %d)\n", acuity_last_error(),    \
                    (int)status_);                                             \
            goto fail;                                                         \
        }                                                                      \
    } while (0)

static void print_lod(const char *label, uint8_t lod) {
    if (lod == ACUITY_LOD_CULLED)
        printf("%sculled", label);
    else
        printf("%sLOD %u", label, (unsigned)lod);
}

int main(int argc, char **argv) {
    AcuityProfile *profile = NULL;
    AcuitySelector *selector = NULL;
    AcuityChange *changed = NULL;
    int exit_code = 1;

    /* ANCHOR: setup */
    if (argc > 1)
        CHECK(acuity_profile_load(argv[1], &profile)); /* from `acuity preprocess` */
    else
        CHECK(acuity_profile_from_bytes((const uint8_t *)DEMO_PROFILE_JSON,
                                        strlen(DEMO_PROFILE_JSON), &profile));
    /* A 1920x1080 screen spanning 90x58.7 degrees of the viewer's field. */
    AcuityDisplay display = {1920, 1080, 90.0f, 58.7f};
    AcuitySettings settings;
    CHECK(acuity_settings_default(&settings));
    settings.track_changes = 1;   /* list the objects whose LOD changed each frame */
    settings.fade_time_s = 0.25f; /* and cross-fade switches over a quarter second */
    CHECK(acuity_selector_new(&display, &settings, &selector));
    uint32_t rock;
    CHECK(acuity_selector_add_profile(selector, profile, &rock));
    CHECK(acuity_profile_free(profile)); /* the selector keeps its own copy */
    profile = NULL;
    AcuityObjectDesc desc = {
        .center = {0.0, 0.0, -20.0},        /* world units, double */
        .rotation = {0.0f, 0.0f, 0.0f, 1.0f}, /* object frame -> world (x, y, z, w) */
        .radius = 0.5f,                     /* profile's bounding_radius x scale */
        .profile = rock,
    };
    AcuityObject hero;
    CHECK(acuity_selector_add_object(selector, &desc, &hero));
    /* ANCHOR_END: setup */

    /* A field of 400 more rocks along the -Z axis, 2 world units apart. */
    AcuityObject rocks[400];
    for (int i = 0; i < 400; i++) {
        double x = (double)(i % 20) - 9.5, z = -2.0 * (double)(i / 20) - 3.0;
        desc.center = (AcuityVec3d){2.0 * x, 0.0, z};
        CHECK(acuity_selector_add_object(selector, &desc, &rocks[i]));
    }
    /* The hero rock keeps more detail; another never goes finer than
     * LOD 1; a third leaves the scene. */
    CHECK(acuity_selector_set_bias(selector, hero, 4.0f));
    CHECK(acuity_selector_set_lod_range(selector, rocks[211], 1, UINT32_MAX));
    CHECK(acuity_selector_remove_object(selector, rocks[399]));

    /* Fly forward at 3 units/s for two seconds at 60 Hz, eyes on the
     * screen's centre. */
    size_t capacity = 402; /* at most every object changes in a frame */
    changed = malloc(capacity * sizeof *changed);
    if (!changed)
        goto fail;
    size_t changes = 0;
    for (int frame = 0; frame < 120; frame++) {
        /* ANCHOR: frame */
        AcuityFrame input;
        CHECK(acuity_frame_default(&input)); /* looks along -Z, +Y up; gaze at the centre */
        input.camera_position = (AcuityVec3d){0.0, 1.0, -0.05 * frame};
        input.dt_s = 1.0f / 60.0f;
        CHECK(acuity_selector_select(selector, &input));
        /* A renderer swaps meshes only for the objects in the change list. */
        size_t count;
        CHECK(acuity_selector_changes(selector, changed, capacity, &count));
        for (size_t i = 0; i < count; i++) {
            uint32_t new_lod = changed[i].lod; /* ACUITY_LOD_CULLED: culled */
            (void)new_lod;
        }
        /* ANCHOR_END: frame */
        changes += count;
        if (frame % 20 == 19) {
            AcuityStats stats;
            CHECK(acuity_selector_stats(selector, &stats));
            printf("frames %3d-%3d: %3llu rocks visible, %6llu triangles, "
                   "%3zu changes (LOD or culled), %2llu cross-fading now\n",
                   frame - 19, frame, (unsigned long long)stats.visible,
                   (unsigned long long)stats.triangles, changes,
                   (unsigned long long)stats.fading);
            changes = 0;
        }
    }
    /* Rock 169 is the hero's neighbour: 1 unit to the left, 1 nearer. */
    uint8_t hero_lod, other;
    CHECK(acuity_selector_lod(selector, hero, &hero_lod));
    CHECK(acuity_selector_lod(selector, rocks[169], &other));
    print_lod("the hero rock (bias 4) draws ", hero_lod);
    print_lod(", its neighbour ", other);
    printf("\n");
    exit_code = 0;

fail:
    free(changed);
    acuity_selector_free(selector);
    acuity_profile_free(profile);
    return exit_code;
}
