/* commands.h — the CLI's subcommands. Each takes the arguments after its
 * name and returns the process exit status (0 ok, 1 runtime error, 2 usage). */
#ifndef RTGI_COMMANDS_H
#define RTGI_COMMANDS_H

int cmd_render(int argc, char **argv);
void cmd_render_help(void);
int cmd_reference(int argc, char **argv);
void cmd_reference_help(void);
int cmd_view(int argc, char **argv);
void cmd_view_help(void);
int cmd_compare(int argc, char **argv);
void cmd_compare_help(void);
int cmd_probe(int argc, char **argv);
int cmd_bench(int argc, char **argv);
void cmd_bench_help(void);
void cmd_probe_help(void);

#endif
