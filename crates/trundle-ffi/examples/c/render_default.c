/*
 * render_default: Trundle's default preset, limiter off, as a 48 kHz stereo 32-bit float WAV
 * file, sample for sample what
 *
 *     trundle render --seconds SECONDS --seed SEED --no-normalize --set limiter=off --format f32
 *
 * writes. Usage: render_default OUT.wav SECONDS SEED
 *
 * Build: `cargo build --release -p trundle-ffi` at the workspace root, then
 * `make -C crates/trundle-ffi/examples/c`.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "trundle.h"

#define RATE_HZ 48000
#define BLOCK_FRAMES 4096

static int fail(const char *what) {
    fprintf(stderr, "render_default: %s: %s\n", what, trundle_last_error());
    return 1;
}

static void put_u16(unsigned char *p, uint16_t v) {
    p[0] = (unsigned char)(v & 0xff);
    p[1] = (unsigned char)(v >> 8);
}

static void put_u32(unsigned char *p, uint32_t v) {
    put_u16(p, (uint16_t)(v & 0xffff));
    put_u16(p + 2, (uint16_t)(v >> 16));
}

/* RIFF/WAVE, WAVE_FORMAT_IEEE_FLOAT (3): a WAVEFORMATEX `fmt ` chunk, the `fact` chunk that
 * non-PCM formats carry, and the `data` chunk's header. */
static int write_header(FILE *f, uint32_t frames) {
    unsigned char h[58];
    uint32_t data_bytes = frames * 2u * 4u;
    memcpy(h, "RIFF", 4);
    put_u32(h + 4, 50u + data_bytes);
    memcpy(h + 8, "WAVE", 4);
    memcpy(h + 12, "fmt ", 4);
    put_u32(h + 16, 18);                 /* fmt chunk size */
    put_u16(h + 20, 3);                  /* IEEE float */
    put_u16(h + 22, 2);                  /* channels */
    put_u32(h + 24, RATE_HZ);            /* frames per second */
    put_u32(h + 28, RATE_HZ * 2u * 4u);  /* bytes per second */
    put_u16(h + 32, 2 * 4);              /* bytes per frame */
    put_u16(h + 34, 32);                 /* bits per sample */
    put_u16(h + 36, 0);                  /* no extension */
    memcpy(h + 38, "fact", 4);
    put_u32(h + 42, 4);
    put_u32(h + 46, frames);             /* sample frames */
    memcpy(h + 50, "data", 4);
    put_u32(h + 54, data_bytes);
    return fwrite(h, 1, sizeof h, f) == sizeof h ? 0 : -1;
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
    static unsigned char bytes[BLOCK_FRAMES * 8];
    int ok = write_header(f, frames) == 0;
    for (uint32_t done = 0; ok && done < frames;) {
        size_t n = frames - done < BLOCK_FRAMES ? frames - done : BLOCK_FRAMES;
        if (trundle_scene_render(scene, left, right, n) != TRUNDLE_STATUS_OK) {
            fclose(f);
            trundle_scene_destroy(scene);
            return fail("trundle_scene_render");
        }
        for (size_t i = 0; i < n; i++) {
            uint32_t l, r;
            memcpy(&l, &left[i], 4);
            memcpy(&r, &right[i], 4);
            put_u32(bytes + 8 * i, l);
            put_u32(bytes + 8 * i + 4, r);
        }
        ok = fwrite(bytes, 8, n, f) == n;
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
