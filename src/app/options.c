/* options.c — see options.h. */
#include "app/options.h"

#include <string.h>

#include "base/util.h"

const OptionDesc *options_find(const OptionDesc *table, const char *opt)
{
    for (const OptionDesc *d = table; d->name; d++)
        if (!strcmp(d->name, opt))
            return d;
    return NULL;
}

int options_take(const OptionDesc *table, const char *opt, CliArgs *a, void *out)
{
    const OptionDesc *d = options_find(table, opt);
    if (!d)
        return 0;
    const char *text = NULL;
    if (value_takes_argument(&d->value) && !(text = cli_value(a)))
        return -1;
    if (d->check && text && !d->check(opt, text))
        return -1;
    if (!value_parse_text(&d->value, opt, text, out))
        return -1;
    if (d->given != OPTION_NO_FLAG)
        *(bool *)((char *)out + d->given) = true;
    return 1;
}

int options_take_setting(const char *opt, CliArgs *a, Settings *set, bool given[])
{
    const SettingDesc *d = settings_find_option(opt);
    if (!d)
        return 0;
    const char *text = NULL;
    if (d->type != VALUE_FLAG && !(text = cli_value(a)))
        return -1;
    if (!settings_parse_cli(d, opt, text, set))
        return -1;
    given[d - settings_table] = true;
    return 1;
}

void options_unknown(const char *opt, const OptionDesc *const *tables, bool settings)
{
    enum { CAP = 512 };
    const char *known[CAP];
    int n = 0;
    for (int t = 0; tables[t]; t++)
        options_names(tables[t], known, &n, CAP);
    for (int i = 0; settings && i < settings_count && n < CAP - 2; i++) {
        known[n++] = settings_table[i].option;
        const char *old = settings_old_option(&settings_table[i]); /* a typo of an old spelling */
        if (old)
            known[n++] = old;
    }
    known[n] = NULL;
    cli_unknown_option(opt, known);
}

/* The row named `opt` in any of the tables, or NULL. */
static const OptionDesc *find_in(const OptionDesc *const *tables, const char *opt)
{
    const OptionDesc *d = NULL;
    for (int t = 0; tables[t] && !d; t++)
        d = options_find(tables[t], opt);
    return d;
}

int options_parse(int argc, char **argv, const OptionSet *os, void *out)
{
    CliArgs a = {.argc = argc, .argv = argv};
    const char *opt;
    while ((opt = cli_next(&a))) {
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            os->help();
            return -1;
        }
        if (os->elsewhere && !find_in(os->tables, opt) && options_find(os->elsewhere, opt)) {
            usage_error(NULL, "%s is an option of 'rtgi %s'", opt, os->elsewhere_command);
            return 2;
        }
        int took = 0;
        for (int t = 0; os->tables[t] && !took; t++)
            took = options_take(os->tables[t], opt, &a, out);
        if (!took && os->set)
            took = options_take_setting(opt, &a, os->set, os->given);
        if (took < 0)
            return 2;
        if (!took) {
            options_unknown(opt, os->tables, os->set != NULL);
            return 2;
        }
    }
    return cli_failed(&a) ? 2 : 0;
}

void options_names(const OptionDesc *table, const char **out, int *n, int cap)
{
    for (const OptionDesc *d = table; d->name && *n < cap - 1; d++)
        out[(*n)++] = d->name;
    out[*n] = NULL;
}

/* Prints `text` from column `indent` on, wrapped at 100 columns. */
static void print_wrapped(FILE *f, const char *text, int indent, int column)
{
    const int width = 100;
    const char *p = text;
    while (*p) {
        int room = width - column;
        int len = (int)strlen(p);
        int cut = len;
        if (len > room) {
            cut = room;
            while (cut > 0 && p[cut] != ' ')
                cut--;
            if (cut == 0) /* one long word */
                for (cut = room; p[cut] && p[cut] != ' ';)
                    cut++;
        }
        fprintf(f, "%.*s\n", cut, p);
        p += cut;
        while (*p == ' ')
            p++;
        if (*p)
            fprintf(f, "%*s", indent, "");
        column = indent;
    }
}

void options_print_help(FILE *f, const OptionDesc *table, const void *defaults)
{
    for (const OptionDesc *d = table; d->name; d++) {
        char arg[160], placeholder[96], line[768];
        if (d->arg)
            snprintf(placeholder, sizeof placeholder, "%s", d->arg);
        else
            value_placeholder(&d->value, placeholder, sizeof placeholder);
        snprintf(arg, sizeof arg, "%s%s%s", d->name, placeholder[0] ? " " : "", placeholder);
        /* A help line that says its default itself ("(default: the scene's)") keeps it. */
        if (d->value.type != VALUE_FLAG && defaults && !strstr(d->help, "(default") && !strstr(d->help, "default:")) {
            char value[256];
            value_format(&d->value, defaults, value, sizeof value);
            snprintf(line, sizeof line, "%s (default %s)", d->help, value);
        } else {
            snprintf(line, sizeof line, "%s", d->help);
        }
        int column = fprintf(f, "  %-28s ", arg);
        if (column > 31) { /* a long argument: the help on the next line */
            fprintf(f, "\n%31s", "");
            column = 31;
        }
        print_wrapped(f, line, 31, column);
    }
}
