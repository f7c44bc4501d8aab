/* log.h — tagged, levelled log lines on stderr.
 * One line per event: "rtgi: error [scene] scenes/x.json:12: expected ','".
 * Errors are logged where they are detected and then returned; only main
 * decides to exit. */
#ifndef RTGI_LOG_H
#define RTGI_LOG_H

typedef enum LogLevel { LOG_DEBUG, LOG_INFO, LOG_WARN, LOG_ERROR, LOG_QUIET } LogLevel;

/* Messages below `level` are dropped. Default: LOG_INFO. */
void log_set_level(LogLevel level);
LogLevel log_get_level(void);
/* A hook sees every message (before the level filter, without the prefix),
 * e.g. the window's panel showing the last shader error; NULL removes it. */
typedef void (*LogHook)(LogLevel level, const char *tag, const char *message, void *user);
void log_set_hook(LogHook hook, void *user);
void log_msg(LogLevel level, const char *tag, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Progress of long work on stderr, a bare line ("render: frame 2 of 3
 * took 4.1 s; ...") unless the level is above LOG_INFO (--quiet). */
void log_progress(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* The seconds after which long work reports progress: `dflt`, or the
 * environment's RTGI_PROGRESS_S when set (tests set 0 to see the lines of
 * short runs). */
double log_progress_seconds(double dflt);

#define log_debug(tag, ...) log_msg(LOG_DEBUG, tag, __VA_ARGS__)
#define log_info(tag, ...) log_msg(LOG_INFO, tag, __VA_ARGS__)
#define log_warn(tag, ...) log_msg(LOG_WARN, tag, __VA_ARGS__)
#define log_error(tag, ...) log_msg(LOG_ERROR, tag, __VA_ARGS__)

#endif
