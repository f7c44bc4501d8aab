/* sequence.c — frame-numbered output patterns and the optional video. */
#include "app/sequence.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app/cli.h"
#include "base/log.h"
#include "base/util.h"

/* The pattern's frame number: where its '%' starts, its width and zero
 * flag, and where the conversion ends. false if it has not exactly one
 * (other '%' only as "%%"). */
static bool find_number(const char *pattern, size_t *at, size_t *end, int *width, bool *zero)
{
    int found = 0;
    for (size_t i = 0; pattern[i]; i++) {
        if (pattern[i] != '%')
            continue;
        if (pattern[i + 1] == '%') {
            i++;
            continue;
        }
        size_t j = i + 1;
        bool z = pattern[j] == '0';
        j += z;
        int w = 0;
        while (pattern[j] >= '0' && pattern[j] <= '9' && w < 100)
            w = 10 * w + (pattern[j++] - '0');
        if (pattern[j] != 'd' || w > 9 || found++)
            return false;
        *at = i;
        *end = j + 1;
        *width = w;
        *zero = z;
        i = j;
    }
    return found == 1;
}

bool sequence_pattern_check(const char *opt, const char *pattern)
{
    size_t at, end;
    int width;
    bool zero;
    if (find_number(pattern, &at, &end, &width, &zero))
        return true;
    usage_error(NULL, "%s: '%s' must hold one frame number, %%d or %%0Nd (e.g. out/frame_%%04d.exr), and no other "
              "%% than %%%%", opt, pattern);
    return false;
}

void sequence_path(const char *pattern, int i, char *out, size_t cap)
{
    size_t at = 0, end = 0;
    int width = 0;
    bool zero = false;
    find_number(pattern, &at, &end, &width, &zero);
    StrBuf b = {0};
    for (size_t k = 0; pattern[k]; k++) {
        if (k == at) {
            strbuf_printf(&b, zero ? "%0*d" : "%*d", width, i);
            k = end - 1;
        } else {
            strbuf_append(&b, pattern + k, 1);
            k += pattern[k] == '%' && pattern[k + 1] == '%'; /* "%%" is one '%' */
        }
    }
    snprintf(out, cap, "%s", b.data && !b.failed ? b.data : "");
    free(b.data);
}

int sequence_check_options(const SequenceOptions *o)
{
    if (!o->animate) {
        const char *seq = o->frames_given && o->frames_need_animate ? "--frames"
                        : o->fps > 0                                ? "--fps"
                        : o->video                                  ? "--video"
                                                                    : NULL;
        if (seq) {
            usage_error(NULL, "%s: needs --animate (a sequence of frames)", seq);
            return 2;
        }
        return 0;
    }
    if (o->time >= 0) {
        usage_error(NULL, "%s and --animate: give one (%s renders one instant)", o->time_opt, o->time_opt);
        return 2;
    }
    if (!o->frames_given || o->frames < 1) {
        usage_error(NULL, "--animate: needs --frames N (N >= 1), the frames of the sequence");
        return 2;
    }
    if (o->single) {
        usage_error(NULL, "%s: not with --animate (a sequence writes --out's frames only, e.g. --out "
                  "DIR/frame_%%04d.png)", o->single);
        return 2;
    }
    if (o->video && !util_ends_with(o->video, ".mp4")) {
        usage_error(NULL, "--video: '%s' must end in .mp4", o->video);
        return 2;
    }
    return sequence_pattern_check("--out", o->out) ? 0 : 2;
}

void sequence_remove(const char *pattern, int n)
{
    char path[UTIL_PATH_MAX];
    for (int i = 0; i < n; i++) {
        sequence_path(pattern, i, path, sizeof path);
        remove(path);
    }
}

bool sequence_ffmpeg_found(void)
{
    const char *path = getenv("PATH");
    if (!path)
        return false;
    char *dirs = util_strndup(path, strlen(path)), *cursor = dirs;
    bool found = false;
    while (dirs && cursor && !found) {
        char *colon = strchr(cursor, ':');
        if (colon)
            *colon = 0;
        char exe[UTIL_PATH_MAX];
        snprintf(exe, sizeof exe, "%s/ffmpeg", *cursor ? cursor : ".");
        found = access(exe, X_OK) == 0;
        cursor = colon ? colon + 1 : NULL;
    }
    free(dirs);
    return found;
}

bool sequence_write_video(const char *png_pattern, int n, double fps, const char *out)
{
    (void)n; /* ffmpeg reads frames from 0 until the first missing one */
    char rate[32];
    snprintf(rate, sizeof rate, "%.6g", fps);
    /* ffmpeg's image2 demuxer takes the printf pattern as it is. */
    pid_t pid = fork();
    if (pid < 0) {
        log_error("render", "--video %s: cannot start ffmpeg", out);
        return false;
    }
    if (pid == 0) {
        execlp("ffmpeg", "ffmpeg", "-y", "-loglevel", "error", "-framerate", rate, "-start_number", "0", "-i",
               png_pattern, "-c:v", "libx264", "-pix_fmt", "yuv420p",
               "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", out, (char *)NULL);
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && access(out, F_OK) == 0)
        return true;
    log_error("render", "--video %s: ffmpeg failed (exit status %d); the frames are written", out,
              WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return false;
}
