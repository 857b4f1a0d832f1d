/*
 * wav.h: a 32-bit float stereo WAV file written by hand, for the examples: RIFF/WAVE,
 * WAVE_FORMAT_IEEE_FLOAT (3) in a WAVEFORMATEX `fmt ` chunk, the `fact` chunk non-PCM
 * formats carry, the `data` chunk. Little-endian whatever the machine.
 */
#ifndef TRUNDLE_EXAMPLE_WAV_H
#define TRUNDLE_EXAMPLE_WAV_H

#include <stdint.h>
#include <stdio.h>
#include <string.h>

static void wav_put_u16(unsigned char *p, uint16_t v) {
    p[0] = (unsigned char)(v & 0xff);
    p[1] = (unsigned char)(v >> 8);
}

static void wav_put_u32(unsigned char *p, uint32_t v) {
    wav_put_u16(p, (uint16_t)(v & 0xffff));
    wav_put_u16(p + 2, (uint16_t)(v >> 16));
}

/* The header of a file of `frames` stereo frames at `rate_hz`; 0 on success. */
static int wav_write_header(FILE *f, uint32_t frames, uint32_t rate_hz) {
    unsigned char h[58];
    uint32_t data_bytes = frames * 2u * 4u;
    memcpy(h, "RIFF", 4);
    wav_put_u32(h + 4, 50u + data_bytes);
    memcpy(h + 8, "WAVE", 4);
    memcpy(h + 12, "fmt ", 4);
    wav_put_u32(h + 16, 18);            /* fmt chunk size */
    wav_put_u16(h + 20, 3);             /* IEEE float */
    wav_put_u16(h + 22, 2);             /* channels */
    wav_put_u32(h + 24, rate_hz);       /* frames per second */
    wav_put_u32(h + 28, rate_hz * 8u);  /* bytes per second */
    wav_put_u16(h + 32, 8);             /* bytes per frame */
    wav_put_u16(h + 34, 32);            /* bits per sample */
    wav_put_u16(h + 36, 0);             /* no extension */
    memcpy(h + 38, "fact", 4);
    wav_put_u32(h + 42, 4);
    wav_put_u32(h + 46, frames);        /* sample frames */
    memcpy(h + 50, "data", 4);
    wav_put_u32(h + 54, data_bytes);
    return fwrite(h, 1, sizeof h, f) == sizeof h ? 0 : -1;
}

/* `n` frames (at most 4096) of `left` and `right`, interleaved; 0 on success. */
static int wav_write_frames(FILE *f, const float *left, const float *right, size_t n) {
    static unsigned char bytes[4096 * 8];
    if (n > 4096)
        return -1;
    for (size_t i = 0; i < n; i++) {
        uint32_t l, r;
        memcpy(&l, &left[i], 4);
        memcpy(&r, &right[i], 4);
        wav_put_u32(bytes + 8 * i, l);
        wav_put_u32(bytes + 8 * i + 4, r);
    }
    return fwrite(bytes, 8, n, f) == n ? 0 : -1;
}

#endif
