/*
 * contact_stream: what a game does with Trundle's contact stream. A glass marble (radius
 * 1 cm) is dropped from 20 cm onto a wooden table while moving sideways at 0.5 m/s: it
 * strikes, bounces, lands again, rolls and slows to rest. A toy physics step at 60 Hz stands
 * in for the game's engine; each frame it submits the marble's contact (if it touches),
 * ends the frame and renders 800 audio frames. Writes a 48 kHz stereo float WAV and prints
 * the voice log: one voice, struck at each landing, rolling, ended at rest.
 *
 * Usage: contact_stream OUT.wav
 * Build: `cargo build --release -p trundle-ffi`, then `make -C examples/c`.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "trundle.h"
#include "wav.h"

#define RATE_HZ 48000
#define PHYSICS_HZ 60
#define AUDIO_PER_FRAME (RATE_HZ / PHYSICS_HZ)
#define SECONDS 5

static int fail(const char *what) {
    fprintf(stderr, "contact_stream: %s: %s\n", what, trundle_last_error());
    return 1;
}

static void print_events(TrundleStream *stream, uint64_t *starts) {
    static const char *kinds[] = {"start", "impact", "motion", "end"};
    static const char *motions[] = {"impact", "roll", "rub"};
    static const char *ends[] = {"rest", "lost", "removed"};
    TrundleEvent events[16];
    size_t n = 0;
    do {
        if (trundle_stream_poll_events(stream, events, 16, &n) != TRUNDLE_STATUS_OK) {
            fail("trundle_stream_poll_events");
            return;
        }
        for (size_t i = 0; i < n; i++) {
            const TrundleEvent *e = &events[i];
            printf("frame %4llu  voice %llu  pair %llu  %-6s", (unsigned long long)e->frame,
                   (unsigned long long)e->voice, (unsigned long long)e->pair, kinds[e->kind]);
            if (e->kind == TRUNDLE_EVENT_KIND_IMPACT)
                printf("  %.2f m/s", e->value);
            if (e->kind == TRUNDLE_EVENT_KIND_MOTION && e->detail < 3)
                printf("  %s", motions[e->detail]);
            if (e->kind == TRUNDLE_EVENT_KIND_END && e->detail < 3)
                printf("  %s", ends[e->detail]);
            printf("\n");
            if (e->kind == TRUNDLE_EVENT_KIND_START)
                (*starts)++;
        }
    } while (n == 16);
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: contact_stream OUT.wav\n");
        return 2;
    }
    TrundleStreamSettings settings;
    TrundleMaterial materials[2];
    if (trundle_stream_settings_default(&settings) != TRUNDLE_STATUS_OK ||
        trundle_material_default(TRUNDLE_MATERIAL_GLASS, &materials[0]) != TRUNDLE_STATUS_OK ||
        trundle_material_default(TRUNDLE_MATERIAL_WOOD, &materials[1]) != TRUNDLE_STATUS_OK)
        return fail("defaults");
    settings.sample_rate_hz = RATE_HZ;
    settings.frame_rate_hz = PHYSICS_HZ;
    TrundleStream *stream = NULL;
    if (trundle_stream_create(&settings, materials, 2, &stream) != TRUNDLE_STATUS_OK)
        return fail("trundle_stream_create");

    FILE *f = fopen(argv[1], "wb");
    if (f == NULL || wav_write_header(f, SECONDS * RATE_HZ, RATE_HZ) != 0) {
        perror("contact_stream: cannot write the output file");
        return 1;
    }
    /* The toy engine: height z above the table (m), vertical speed vz, sideways speed v. */
    const double g = 9.81, radius = 0.01, restitution = 0.45, rolling_decel = 0.2;
    const double dt = 1.0 / PHYSICS_HZ;
    double x = -0.3, z = 0.2, vz = 0.0, v = 0.5;
    uint64_t starts = 0;
    static float left[AUDIO_PER_FRAME], right[AUDIO_PER_FRAME];
    for (int frame = 0; frame < SECONDS * PHYSICS_HZ; frame++) {
        double approach = 0.0;
        int on_table = z == 0.0 && vz == 0.0;
        if (!on_table) { /* flying: fall, and bounce where it lands */
            vz -= g * dt;
            z += vz * dt;
            if (z <= 0.0) {
                approach = -vz; /* speed into the table this frame */
                z = 0.0;
                vz = approach * restitution > 0.05 ? approach * restitution : 0.0;
            }
        } else { /* rolling: slowed by rolling resistance */
            v = v > rolling_decel * dt ? v - rolling_decel * dt : 0.0;
        }
        int touching = z == 0.0;
        x += v * dt;
        if (touching) {
            TrundleContact c = {0};
            c.pair = 1;
            c.body = 1;
            c.normal_speed_m_s = approach;
            c.tangential_speed_m_s = v;
            c.angular_speed_rad_s = v / radius; /* rolling without slip */
            c.radius_m = radius;
            c.point_m[0] = x;
            c.normal[2] = 1.0;
            c.normal_impulse_n_s = 0.01 * g * dt + 0.01 * approach; /* 10 g marble */
            c.materials[0] = 0;
            c.materials[1] = 1;
            if (trundle_stream_submit(stream, &c) != TRUNDLE_STATUS_OK)
                return fail("trundle_stream_submit");
        }
        if (trundle_stream_end_frame(stream) != TRUNDLE_STATUS_OK)
            return fail("trundle_stream_end_frame");
        if (trundle_stream_render(stream, left, right, AUDIO_PER_FRAME) != TRUNDLE_STATUS_OK)
            return fail("trundle_stream_render");
        if (wav_write_frames(f, left, right, AUDIO_PER_FRAME) != 0) {
            perror("contact_stream: cannot write the output file");
            return 1;
        }
        print_events(stream, &starts);
    }
    TrundleStreamStats stats;
    if (trundle_stream_stats(stream, &stats) != TRUNDLE_STATUS_OK)
        return fail("trundle_stream_stats");
    trundle_stream_destroy(stream);
    if (fclose(f) != 0) {
        perror("contact_stream: cannot write the output file");
        return 1;
    }
    printf("voices started: %llu\n", (unsigned long long)stats.voices_started);
    return starts == stats.voices_started ? 0 : 1;
}
