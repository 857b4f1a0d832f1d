/*
 * render_default: Trundle's default preset, limiter off, as a 48 kHz stereo 32-bit float WAV
 * file, sample for sample what
 *
 *     trundle render --seconds SECONDS --seed SEED --no-normalize --set limiter=off --format f32
 *
 * writes. Usage: render_default OUT.wav SECONDS SEED
 *
 * Build: `cargo build --release -p trundle-ffi` at the workspace root, then
 * `make -C examples/c`.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "trundle.h"
#include "wav.h"

#define RATE_HZ 48000
#define BLOCK_FRAMES 4096

static int fail(const char *what) {
    fprintf(stderr, "render_default: %s: %s\n", what, trundle_last_error());
    return 1;
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: render_default OUT.wav SECONDS SEED\n");
        return 2;
    }
    char *end = NULL;
    double seconds = strtod(argv[2], &end);
    if (*argv[2] == '\0' || *end != '\0' || !isfinite(seconds) || seconds <= 0.0 ||
        seconds > 3600.0) {
        fprintf(stderr, "render_default: SECONDS must be a number above 0, at most 3600\n");
        return 2;
    }
    end = NULL;
    unsigned long long seed = strtoull(argv[3], &end, 10);
    if (*argv[3] == '\0' || *argv[3] == '-' || *end != '\0') {
        fprintf(stderr, "render_default: SEED must be a whole number\n");
        return 2;
    }
    /* The CLI's frame count: seconds × rate, rounded half away from zero. */
    uint32_t frames = (uint32_t)llround(seconds * RATE_HZ);

    TrundleScene *scene = NULL;
    if (trundle_scene_create("default", RATE_HZ, (uint64_t)seed, &scene) != TRUNDLE_STATUS_OK)
        return fail("trundle_scene_create");
    if (trundle_scene_set_param_text(scene, "limiter", "off") != TRUNDLE_STATUS_OK)
        return fail("trundle_scene_set_param_text");

    FILE *f = fopen(argv[1], "wb");
    if (f == NULL) {
        perror("render_default: cannot create the output file");
        trundle_scene_destroy(scene);
        return 1;
    }
    static float left[BLOCK_FRAMES], right[BLOCK_FRAMES];
    int ok = wav_write_header(f, frames, RATE_HZ) == 0;
    for (uint32_t done = 0; ok && done < frames;) {
        size_t n = frames - done < BLOCK_FRAMES ? frames - done : BLOCK_FRAMES;
        if (trundle_scene_render(scene, left, right, n) != TRUNDLE_STATUS_OK) {
            fclose(f);
            trundle_scene_destroy(scene);
            return fail("trundle_scene_render");
        }
        ok = wav_write_frames(f, left, right, n) == 0;
        done += (uint32_t)n;
    }
    if (fclose(f) != 0)
        ok = 0;
    trundle_scene_destroy(scene);
    if (!ok) {
        perror("render_default: cannot write the output file");
        return 1;
    }
    printf("%s: %u frames, 48 kHz stereo float, seed %llu (%s)\n", argv[1], frames, seed,
           trundle_version());
    return 0;
}
