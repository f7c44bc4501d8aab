/* value.c — see value.h. */
#include "base/value.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/usage.h"
#include "base/util.h"

static void *at(void *base, size_t off) { return (char *)base + off; }
static const void *cat(const void *base, size_t off) { return (const char *)base + off; }

void value_store_number(const ValueSpec *v, void *base, double x)
{
    switch (v->type) {
    case VALUE_INT:
    case VALUE_CHOICE:
        *(int *)at(base, v->offset) = (int)x;
        break;
    case VALUE_UINT:
        *(unsigned *)at(base, v->offset) = (unsigned)x;
        break;
    case VALUE_FLOAT:
        *(float *)at(base, v->offset) = (float)x;
        break;
    case VALUE_DOUBLE:
        *(double *)at(base, v->offset) = x;
        break;
    case VALUE_BOOL:
    case VALUE_FLAG:
        *(bool *)at(base, v->offset) = x != 0;
        break;
    case VALUE_PAIR:
    case VALUE_SIZE:
        *(int *)at(base, v->offset) = (int)x;
        *(int *)at(base, v->offset2) = (int)x;
        break;
    case VALUE_TEXT:
        break;
    }
}

static size_t value_bytes(const ValueSpec *v)
{
    switch (v->type) {
    case VALUE_FLOAT:
        return sizeof(float);
    case VALUE_DOUBLE:
        return sizeof(double);
    case VALUE_BOOL:
    case VALUE_FLAG:
        return sizeof(bool);
    case VALUE_UINT:
        return sizeof(unsigned);
    case VALUE_TEXT:
        return sizeof(const char *);
    default:
        return sizeof(int);
    }
}

void value_copy(const ValueSpec *v, void *dst, const void *src)
{
    memcpy(at(dst, v->offset), cat(src, v->offset), value_bytes(v));
    if (v->type == VALUE_PAIR || v->type == VALUE_SIZE)
        memcpy(at(dst, v->offset2), cat(src, v->offset2), sizeof(int));
}

void value_format(const ValueSpec *v, const void *base, char *out, size_t cap)
{
    switch (v->type) {
    case VALUE_INT:
        snprintf(out, cap, "%d", *(const int *)cat(base, v->offset));
        break;
    case VALUE_UINT:
        snprintf(out, cap, "%u", *(const unsigned *)cat(base, v->offset));
        break;
    case VALUE_FLOAT:
        snprintf(out, cap, "%g", (double)*(const float *)cat(base, v->offset));
        break;
    case VALUE_DOUBLE:
        snprintf(out, cap, "%g", *(const double *)cat(base, v->offset));
        break;
    case VALUE_BOOL:
    case VALUE_FLAG:
        snprintf(out, cap, "%s", *(const bool *)cat(base, v->offset) ? "on" : "off");
        break;
    case VALUE_CHOICE:
        snprintf(out, cap, "%s", v->choices[*(const int *)cat(base, v->offset)]);
        break;
    case VALUE_PAIR:
    case VALUE_SIZE:
        snprintf(out, cap, "%dx%d", *(const int *)cat(base, v->offset), *(const int *)cat(base, v->offset2));
        break;
    case VALUE_TEXT: {
        const char *s = *(const char *const *)cat(base, v->offset);
        snprintf(out, cap, "%s", s ? s : "none");
        break;
    }
    }
}

/* "a|b|c" (sep "|") or "a, b, c" (sep ", ") of the choices. */
static void join_choices(const char *const *choices, const char *sep, char *out, size_t cap)
{
    size_t len = 0;
    out[0] = 0;
    for (int i = 0; choices[i] && len < cap; i++)
        len += (size_t)snprintf(out + len, cap - len, "%s%s", i ? sep : "", choices[i]);
}

void value_placeholder(const ValueSpec *v, char *out, size_t cap)
{
    switch (v->type) {
    case VALUE_FLAG:
        out[0] = 0;
        break;
    case VALUE_BOOL:
        snprintf(out, cap, "on|off");
        break;
    case VALUE_CHOICE:
        join_choices(v->choices, "|", out, cap);
        break;
    case VALUE_PAIR:
        snprintf(out, cap, "NxM");
        break;
    case VALUE_SIZE:
        snprintf(out, cap, "WxH");
        break;
    case VALUE_FLOAT:
    case VALUE_DOUBLE:
        snprintf(out, cap, "X");
        break;
    case VALUE_TEXT:
        snprintf(out, cap, "FILE");
        break;
    default:
        snprintf(out, cap, "N");
        break;
    }
}

void value_describe(const ValueSpec *v, bool json, char *out, size_t cap)
{
    switch (v->type) {
    case VALUE_BOOL:
        snprintf(out, cap, json ? "true or false (or \"on\", \"off\")" : "on or off");
        break;
    case VALUE_FLAG:
        snprintf(out, cap, "true or false");
        break;
    case VALUE_CHOICE:
        join_choices(v->choices, ", ", out, cap);
        break;
    case VALUE_PAIR:
        snprintf(out, cap, "NxM with N, M in [%.10g, %.10g]", v->min, v->max);
        break;
    case VALUE_SIZE:
        snprintf(out, cap, "WxH with W, H in [1, %.10g]", v->max);
        break;
    case VALUE_FLOAT:
    case VALUE_DOUBLE:
        snprintf(out, cap, "a number in [%.10g, %.10g]", v->min, v->max);
        break;
    case VALUE_TEXT:
        snprintf(out, cap, "a file name");
        break;
    default:
        snprintf(out, cap, "an integer in [%.0f, %.0f]", v->min, v->max);
        break;
    }
}

const char *value_check_number(const ValueSpec *v, double x)
{
    if (!isfinite(x))
        return "is not a finite number";
    bool integral = v->type == VALUE_INT || v->type == VALUE_UINT || v->type == VALUE_PAIR || v->type == VALUE_SIZE;
    if (integral && x != floor(x))
        return "is not an integer";
    if (v->type == VALUE_FLOAT && !isfinite((float)x))
        return "overflows a float";
    if (x < v->min || x > v->max)
        return "is out of range";
    return NULL;
}

/* A usage error naming the option, the text and what is allowed. */
static bool fail(const ValueSpec *v, const char *opt, const char *text, const char *problem)
{
    char range[256];
    value_describe(v, false, range, sizeof range);
    usage_error(NULL, "%s: '%s' %s (allowed: %s)", opt, text, problem, range);
    return false;
}

static bool parse_strict_number(const char *text, double *out)
{
    /* Decimal only, but "nan" and "inf" reach strtod to be refused as not
     * finite, which says more. */
    const char *word = text && (*text == '+' || *text == '-') ? text + 1 : text;
    bool special = word && (!strcasecmp(word, "nan") || !strcasecmp(word, "inf") || !strcasecmp(word, "infinity"));
    if (!util_decimal_text(text) && !special)
        return false;
    char *end;
    errno = 0;
    double x = strtod(text, &end);
    if (*end || end == text || errno == ERANGE)
        return false;
    *out = x;
    return true;
}

/* "<a>x<b>" into two numbers; false if it is not of that form. */
static bool split_pair(const char *text, double *a, double *b)
{
    const char *x = strchr(text, 'x');
    if (!x)
        x = strchr(text, 'X');
    char sa[32], sb[32];
    if (!x || (size_t)(x - text) >= sizeof sa || strlen(x + 1) >= sizeof sb)
        return false;
    snprintf(sa, sizeof sa, "%.*s", (int)(x - text), text);
    snprintf(sb, sizeof sb, "%s", x + 1);
    return parse_strict_number(sa, a) && parse_strict_number(sb, b);
}

/* VALUE_TEXT's endings: true if `text` ends in one, else the usage error
 * "<opt>: '<text>' must end in .a, .b or .c". */
static bool check_endings(const ValueSpec *v, const char *opt, const char *text)
{
    if (!v->endings)
        return true;
    char list[128], words[8][16];
    int n = 0;
    for (const char *p = v->endings; *p && n < 8;) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        snprintf(words[n], sizeof words[n], ".%.*s", (int)len, p);
        if (util_ends_with(text, words[n]))
            return true;
        n++;
        p += len + (bar ? 1 : 0);
    }
    size_t len = 0;
    list[0] = 0;
    for (int i = 0; i < n; i++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", i == 0 ? "" : i == n - 1 ? " or " : ", ",
                                words[i]);
    usage_error(NULL, "%s: '%s' must end in %s", opt, text, list);
    return false;
}

bool value_parse_text(const ValueSpec *v, const char *opt, const char *text, void *base)
{
    double x, y;
    const char *problem;
    switch (v->type) {
    case VALUE_FLAG:
        *(bool *)at(base, v->offset) = true;
        return true;
    case VALUE_BOOL:
        if (strcmp(text, "on") && strcmp(text, "off"))
            return fail(v, opt, text, "is not on or off");
        *(bool *)at(base, v->offset) = !strcmp(text, "on");
        return true;
    case VALUE_CHOICE: {
        for (int i = 0; v->choices[i]; i++)
            if (!strcmp(text, v->choices[i])) {
                *(int *)at(base, v->offset) = i;
                return true;
            }
        char list[256];
        join_choices(v->choices, ", ", list, sizeof list);
        usage_error(util_nearest(text, v->choices), "%s: unknown value '%s' (one of %s)", opt, text, list);
        return false;
    }
    case VALUE_SIZE:
        if (!split_pair(text, &x, &y) || x != floor(x) || y != floor(y)) {
            usage_error(NULL, "%s: '%s' is not a size WxH (e.g. 512x512)", opt, text);
            return false;
        }
        if (x < 1 || y < 1 || x > v->max || y > v->max) {
            usage_error(NULL, "%s: %s: width and height must be between 1 and %.0f", opt, text, v->max);
            return false;
        }
        *(int *)at(base, v->offset) = (int)x;
        *(int *)at(base, v->offset2) = (int)y;
        return true;
    case VALUE_PAIR:
        if (!split_pair(text, &x, &y))
            return fail(v, opt, text, "is not of the form NxM");
        if ((problem = value_check_number(v, x)) || (problem = value_check_number(v, y)))
            return fail(v, opt, text, problem);
        *(int *)at(base, v->offset) = (int)x;
        *(int *)at(base, v->offset2) = (int)y;
        return true;
    case VALUE_TEXT:
        if (!check_endings(v, opt, text))
            return false;
        *(const char **)at(base, v->offset) = text;
        return true;
    default:
        if (!parse_strict_number(text, &x))
            return fail(v, opt, text, "is not a number");
        if ((problem = value_check_number(v, x)))
            return fail(v, opt, text, problem);
        value_store_number(v, base, x);
        return true;
    }
}
