/* usage.h — the one style of usage errors every command shares:
 *   "<command>: <what>; did you mean '<near>'? (see rtgi <command> --help)"
 * Parsers (the command line's, the settings table's) log one such line that
 * names the option and the bad value and return false; the command then
 * exits 2. */
#ifndef RTGI_USAGE_H
#define RTGI_USAGE_H

/* The command whose options are parsed ("render"), named by every usage
 * error; main sets it before dispatching. NULL (the default): rtgi itself
 * ("rtgi: ... (see rtgi --help)"). */
void usage_set_command(const char *cmd);
/* The current command's name, or "rtgi". */
const char *usage_command(void);
/* Logs one usage error of the current command in the shared style; `near`
 * (may be NULL) is the suggestion. */
void usage_error(const char *near, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
