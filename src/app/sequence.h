/* sequence.h — image sequences of an animation (`render --animate`,
 * `reference --animate`): output patterns with a frame number, and an
 * optional video through ffmpeg (the Debian package `ffmpeg`, when
 * installed; nothing needs it). */
#ifndef RTGI_SEQUENCE_H
#define RTGI_SEQUENCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Whether `pattern` holds exactly one frame number, %d or %0Nd (N ≤ 9),
 * and no other conversion than %% (printf's). false after a usage error
 * naming option `opt`. */
bool sequence_pattern_check(const char *opt, const char *pattern);
/* The pattern with frame number i into out (cap bytes). */
void sequence_path(const char *pattern, int i, char *out, size_t cap);
/* The time options of `render` or `reference`, to check together. */
typedef struct SequenceOptions {
    bool animate;            /* --animate */
    bool frames_given;       /* --frames was given */
    int frames;              /* its value */
    bool frames_need_animate;/* --frames means nothing without --animate (reference) */
    double fps;              /* --fps (0: not given) */
    double time;             /* the instant option (< 0: not given) */
    const char *time_opt;    /* its name: render --time, reference --at (its --time is a budget) */
    const char *video;       /* --video, or NULL */
    const char *single;      /* an option given that writes one image (--png, ...), or NULL */
    const char *out;         /* --out */
} SequenceOptions;
/* --fps, --video (and --frames where frames_need_animate) only with
 * --animate; time_opt not with it; --animate with --frames N >= 1, none of
 * `single`, a .mp4 --video and a frame pattern in --out. 0, or 2 after a
 * usage error. */
int sequence_check_options(const SequenceOptions *o);
/* Removes frames 0..n-1 of the pattern (a failed sequence leaves none). */
void sequence_remove(const char *pattern, int n);

/* Whether an `ffmpeg` executable is on the PATH. */
bool sequence_ffmpeg_found(void);
/* Writes `out` (H.264 in MP4, or what ffmpeg makes of its extension) from
 * the PNG frames of `png_pattern` (0..n-1) at `fps` frames per second.
 * false after logging (ffmpeg's own messages are on stderr). */
bool sequence_write_video(const char *png_pattern, int n, double fps, const char *out);

#endif
