/* test_settings.c — the settings table: every row round-trips through the
 * scene file and the command line to the same stored value, both reject
 * out-of-range values at each end with a message naming the key or option,
 * the guide (docs/guide.md) lists every row, and the technique table is consistent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gi/gi.h"
#include "app/commands.h"
#include "app/render_options.h"
#include "core/settings.h"
#include "test_util.h"
#include "base/util.h"

/* A value for row d, different from the default and inside the range. */
static void pick_value(const SettingDesc *d, char *cli, size_t cap, char *json, size_t jcap)
{
    switch (d->type) {
    case VALUE_FLAG:
        snprintf(cli, cap, "%s", "");
        snprintf(json, jcap, "true");
        break;
    case VALUE_BOOL:
        snprintf(cli, cap, "%s", d->def != 0 ? "off" : "on");
        snprintf(json, jcap, "%s", d->def != 0 ? "false" : "true");
        break;
    case VALUE_CHOICE: {
        int count = 0;
        while (d->choices[count])
            count++;
        int other = ((int)d->def + 1) % count;
        snprintf(cli, cap, "%s", d->choices[other]);
        snprintf(json, jcap, "\"%s\"", d->choices[other]);
        break;
    }
    case VALUE_PAIR:
        snprintf(cli, cap, "%.0fx%.0f", d->min, d->max);
        snprintf(json, jcap, "[%.0f, %.0f]", d->min, d->max);
        break;
    case VALUE_FLOAT: {
        double v = d->min + 0.37 * (d->max - d->min);
        snprintf(cli, cap, "%.9g", v);
        snprintf(json, jcap, "%.9g", v);
        break;
    }
    default: {
        double v = floor(d->min + 0.37 * (d->max - d->min));
        if (v == d->def)
            v = d->max;
        snprintf(cli, cap, "%.0f", v);
        snprintf(json, jcap, "%.0f", v);
        break;
    }
    }
}


/* Every row: scene file → Scene → RenderSettings, and the command line →
 * RenderOptions → RenderSettings, store the same bytes, not the default.
 * An enum of one choice (gi.gi_visibility_method, until a second method
 * exists) has no other value to store: it round-trips its default. */
static void every_setting_round_trips(void **state)
{
    (void)state;
    Settings def;
    settings_default(&def);
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        bool single = d->type == VALUE_CHOICE && d->choices[0] && !d->choices[1];
        char cli[64], json[64], body[512];
        pick_value(d, cli, sizeof cli, json, sizeof json);
        snprintf(body, sizeof body, "{ \"builtin\": \"cornell\", \"%s\": { \"%s\": %s } }\n", d->family, d->field,
                 json);
        const char *path = test_tmp_file("roundtrip.json", body);

        Scene from_file;
        assert_true(scene_load(&from_file, path));
        RenderOptions o;
        render_options_init(&o, false);
        RenderSettings rs_file, rs_cli;
        render_options_settings(&o, &from_file, &rs_file);

        Scene plain;
        assert_true(scene_load(&plain, "cornell"));
        render_options_init(&o, false);
        char *argv[3] = {(char *)d->option, cli, NULL};
        int argc = d->type == VALUE_FLAG ? 1 : 2;
        assert_int_equal(render_options_parse(&o, argc, argv, cmd_render_help), 0);
        render_options_settings(&o, &plain, &rs_cli);

        Settings a = {rs_file.set.shadow, rs_file.set.gi}, b = {rs_cli.set.shadow, rs_cli.set.gi};
        char va[64], vb[64], vd[64];
        settings_format(d, &a, va, sizeof va);
        settings_format(d, &b, vb, sizeof vb);
        settings_format(d, &def, vd, sizeof vd);
        if (strcmp(va, vb) || (!strcmp(va, vd) && !single))
            fail_msg("%s / %s: file %s, command line %s, default %s", d->option, d->name, va, vb, vd);
        /* Nothing else differs between the two paths. */
        assert_memory_equal(&a.gi, &b.gi, sizeof a.gi);
        assert_memory_equal(&a.shadow, &b.shadow, sizeof a.shadow);
        if (d->type == VALUE_BOOL) { /* a switch also as the command line writes it: "on", "off" */
            Scene from_word;
            snprintf(body, sizeof body, "{ \"builtin\": \"cornell\", \"%s\": { \"%s\": \"%s\" } }\n", d->family,
                     d->field, cli);
            assert_true(scene_load(&from_word, test_tmp_file("roundtrip.json", body)));
            RenderSettings rs_word;
            render_options_init(&o, false); /* no command line over the file */
            render_options_settings(&o, &from_word, &rs_word);
            assert_memory_equal(&rs_word.set.gi, &rs_file.set.gi, sizeof rs_word.set.gi);
            assert_memory_equal(&rs_word.set.shadow, &rs_file.set.shadow, sizeof rs_word.set.shadow);
            scene_free(&from_word);
        }
        scene_free(&from_file);
        scene_free(&plain);
    }
}

/* The setting of row d after `body`, a scene file, is loaded and rendered
 * options are made from it. */
static void settings_from_file(const char *body, Settings *out)
{
    Scene sc;
    assert_true(scene_load(&sc, test_tmp_file("names.json", body)));
    RenderOptions o;
    render_options_init(&o, false);
    RenderSettings rs;
    render_options_settings(&o, &sc, &rs);
    *out = (Settings){rs.set.shadow, rs.set.gi};
    scene_free(&sc);
}

/* The same from the command line `option value` (flags: no value). */
static void settings_from_cli(const char *option, const char *value, Settings *out)
{
    Scene plain;
    assert_true(scene_load(&plain, "cornell"));
    RenderOptions o;
    render_options_init(&o, false);
    char *argv[3] = {(char *)option, (char *)value, NULL};
    assert_int_equal(render_options_parse(&o, value ? 2 : 1, argv, cmd_render_help), 0);
    RenderSettings rs;
    render_options_settings(&o, &plain, &rs);
    *out = (Settings){rs.set.shadow, rs.set.gi};
    scene_free(&plain);
}

/* Each row has one name: "family.field" (its scene object and key; its C
 * field, by the table's ROW macro), and the option "--family-field" with
 * '_' as '-'; no two rows share a name or an option. */
static void every_setting_has_one_name(void **state)
{
    (void)state;
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        char name[128], option[128];
        snprintf(name, sizeof name, "%s.%s", d->family, d->field);
        snprintf(option, sizeof option, "--%s-%s", d->family, d->field);
        for (char *c = option; *c; c++)
            if (*c == '_')
                *c = '-';
        if (strcmp(d->name, name) || strcmp(d->option, option))
            fail_msg("row %d: name %s, option %s; its family and field make %s, %s", i, d->name, d->option, name,
                     option);
        assert_ptr_equal(settings_find_name(d->name), d);
        assert_ptr_equal(settings_find_option(d->option), d);
    }
}

/* The spellings of commit d364f03 (tests/settings_d364f03.inc, generated
 * from that commit's table): each old option and each old scene key (in the
 * old "shadow" or "gi" object) still parses, to exactly what the row's name
 * and option parse to. */
static void old_spellings_still_parse(void **state)
{
    (void)state;
    static const struct {
        const char *group, *key, *option;
    } old[] = {
#include "settings_d364f03.inc"
    };
    int n = (int)(sizeof old / sizeof old[0]), renamed = 0;
    assert_int_equal(n, 58);
    for (int i = 0; i < n; i++) {
        char key[128], cli[64], json[64], body[512];
        snprintf(key, sizeof key, "%s.%s", old[i].group, old[i].key);
        const SettingDesc *d = settings_find_name(key);
        if (!d)
            fail_msg("the old scene key %s names no setting", key);
        if (settings_find_option(old[i].option) != d)
            fail_msg("the old option %s is not %s's (%s)", old[i].option, d->name, d->option);
        renamed += strcmp(key, d->name) || strcmp(old[i].option, d->option);
        pick_value(d, cli, sizeof cli, json, sizeof json);
        const char *value = d->type == VALUE_FLAG ? NULL : cli;
        Settings by_old, by_new, file_old, file_new;
        settings_from_cli(old[i].option, value, &by_old);
        settings_from_cli(d->option, value, &by_new);
        snprintf(body, sizeof body, "{ \"builtin\": \"cornell\", \"%s\": { \"%s\": %s } }\n", old[i].group,
                 old[i].key, json);
        settings_from_file(body, &file_old);
        snprintf(body, sizeof body, "{ \"builtin\": \"cornell\", \"%s\": { \"%s\": %s } }\n", d->family,
                 d->field, json);
        settings_from_file(body, &file_new);
        char a[64], b[64], c[64], e[64];
        settings_format(d, &by_old, a, sizeof a);
        settings_format(d, &by_new, b, sizeof b);
        settings_format(d, &file_old, c, sizeof c);
        settings_format(d, &file_new, e, sizeof e);
        if (memcmp(&by_old, &by_new, sizeof by_old) || memcmp(&file_old, &file_new, sizeof file_old) ||
            memcmp(&by_old, &file_old, sizeof by_old))
            fail_msg("%s %s: %s; %s %s: %s; file %s: %s; file %s: %s", old[i].option, cli, a, d->option, cli, b, key, c,
                     d->name, e);
    }
    print_message("%d old spellings parse as their rows' names (%d of them renamed)\n", n, renamed);
}

/* Values just outside each end of every numeric row are rejected by both
 * parsers, naming the option (exit 2) or the file's key (exit 1). */
static void out_of_range_is_rejected_by_both(void **state)
{
    (void)state;
    int checked = 0;
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        if (d->type != VALUE_INT && d->type != VALUE_UINT && d->type != VALUE_FLOAT &&
            d->type != VALUE_PAIR)
            continue;
        for (int end = 0; end < 2; end++) {
            double step = d->type == VALUE_FLOAT ? fmax(fabs(end ? d->max : d->min) * 0.5, 1e-3) : 1.0;
            double v = end ? d->max + step : d->min - step;
            char cli[64], json[96], body[512], key[128];
            if (d->type == VALUE_PAIR) {
                snprintf(cli, sizeof cli, "%.0fx%.0f", d->min, v);
                snprintf(json, sizeof json, "[%.0f, %.0f]", d->min, v);
            } else {
                snprintf(cli, sizeof cli, "%.9g", v);
                snprintf(json, sizeof json, "%.9g", v);
            }
            char *err = NULL;
            int rc = test_run_cli(&err, "render", "--size", "8x8", (char *)d->option, cli, NULL);
            test_expect_cli_error(rc, err, 2, d->option, "out of range");
            snprintf(body, sizeof body, "{ \"builtin\": \"cornell\", \"%s\": { \"%s\": %s } }\n", d->family, d->field,
                     json);
            const char *path = test_tmp_file("range.json", body);
            snprintf(key, sizeof key, "%s", d->name);
            rc = test_run_cli(&err, "render", "--size", "8x8", "--scene", path, NULL);
            test_expect_cli_error(rc, err, 1, key, "out of range");
            checked++;
        }
    }
    print_message("%d out-of-range values rejected by both parsers\n", checked);
    assert_true(checked >= 40);
}

/* The crash of issue 8/9: a Poisson-disk count beyond the array, from a
 * scene file (the command line already capped it). Also NaN-like and
 * non-integer values, wrong types, unknown and duplicate keys. */
static void bad_scene_settings(void **state)
{
    (void)state;
    static const struct {
        const char *body, *n1, *n2;
    } cases[] = {
        {"{\"builtin\":\"cornell\",\"shadow\":{\"pcf_samples\":500}}", "shadow.pcf_samples", "out of range"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"pcf_samples\":1000}}", "shadow.pcf_samples", "out of range"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"blocker_samples\":65}}", "shadow.blocker_samples", "out of range"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"map_size\":0}}", "shadow.map_size", "out of range"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"map_size\":-5}}", "shadow.map_size", "out of range"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"map_size\":100000}}", "shadow.map_size", "out of range"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"map_size\":512.5}}", "shadow.map_size", "not an integer"},
        {"{\"builtin\":\"cornell\",\"shadow\":{\"bias_const\":1e400}}", "shadow.bias_const", "finite"},
        {"{\"builtin\":\"cornell\",\"gi\":{\"r_max\":\"big\"}}", "gi.r_max", "must be a number"},
        {"{\"builtin\":\"cornell\",\"gi\":{\"weighting\":\"fast\"}}", "gi.weighting", "choices"},
        {"{\"builtin\":\"cornell\",\"gi\":{\"interleave\":[4]}}", "gi.interleave", "[n, m]"},
        {"{\"builtin\":\"cornell\",\"gi\":{\"interleave_blur\":1}}", "gi.interleave_blur", "true or false"},
        {"{\"builtin\":\"cornell\",\"gi\":{\"interleave_blur\":\"yes\"}}", "gi.interleave_blur", "\"on\", \"off\""},
        {"{\"builtin\":\"cornell\",\"gi\":{\"exhaustive\":\"on\"}}", "gi.exhaustive", "true or false"},
        {"{\"builtin\":\"cornell\",\"gi\":{\"rsm_sise\":64}}", "gi.rsm_sise", "did you mean \"rsm_size\""},
        {"{\"builtin\":\"cornell\",\"gi\":{\"samples\":64,\"samples\":32}}", "gi.samples", "duplicate key"},
        {"{\"builtin\":\"cornell\",\"gi\":[1,2]}", "gi", "must be an object"},
        /* The families' objects, and a setting in both its family's and the old object. */
        {"{\"builtin\":\"cornell\",\"rsm\":{\"sampels\":64}}", "rsm.sampels", "did you mean \"samples\""},
        {"{\"builtin\":\"cornell\",\"vct\":7}", "vct", "must be an object"},
        {"{\"builtin\":\"cornell\",\"lpv\":{\"size\":1}}", "lpv.size", "out of range"},
        {"{\"builtin\":\"cornell\",\"rsm\":{\"samples\":8},\"gi\":{\"samples\":4}}", "gi.samples",
         "rsm.samples is also given in the object \"rsm\""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *path = test_tmp_file("bad_settings.json", cases[i].body);
        char *err = NULL;
        int rc = test_run_cli(&err, "render", "--size", "8x8", "--scene", path, NULL);
        test_expect_cli_error(rc, err, 1, cases[i].n1, cases[i].n2);
    }
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--size", "8x8", "--pcf-samples", "1000", NULL);
    test_expect_cli_error(rc, err, 2, "--pcf-samples", "out of range");
    rc = test_run_cli(&err, "render", "--size", "8x8", "--rsm-weighting", "fast", NULL);
    test_expect_cli_error(rc, err, 2, "--rsm-weighting", "paper, unbiased");
    rc = test_run_cli(&err, "render", "--size", "8x8", "--interleave-blur", "maybe", NULL);
    test_expect_cli_error(rc, err, 2, "--interleave-blur", "on or off");
    rc = test_run_cli(&err, "render", "--size", "8x8", "--bias-const", "nan", NULL);
    test_expect_cli_error(rc, err, 2, "--bias-const", "finite");
    /* In range, but more than the GPU memory budget (here 2 GiB; a 4096²
     * cube RSM takes 2.5 GiB): refused before anything is allocated, naming
     * the setting. */
    setenv("RTGI_GPU_BUDGET_MIB", "2048", 1);
    rc = test_run_cli(&err, "render", "--size", "8x8", "--gi", "rsm", "--rsm-size", "4096", NULL);
    unsetenv("RTGI_GPU_BUDGET_MIB");
    test_expect_cli_error(rc, err, 1, "rsm.size 4096", "budget");
    rc = test_run_cli(&err, "render", "--size", "16384x16384", NULL);
    test_expect_cli_error(rc, err, 1, "--size 16384x16384", "budget");
    /* The scene's own textures and buffers count too (a 2048² texture and
     * its mips, RGBA16F: 42 MiB, over a 16 MiB budget), named by the scene
     * file. */
    enum { T = 2048 };
    uint8_t *grey = malloc(3u * T * T);
    assert_non_null(grey);
    memset(grey, 128, 3u * T * T);
    char png[512];
    snprintf(png, sizeof png, "%s/budget_albedo.png", RTGI_TEST_TMP);
    assert_true(image_write_png8(png, T, T, grey));
    free(grey);
    test_tmp_file("budget_quad.mtl", "newmtl m\nKd 1 1 1\nmap_Kd budget_albedo.png\n");
    const char *obj = test_tmp_file("budget_quad.obj", "mtllib budget_quad.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\n"
                                                       "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 1 0\nusemtl m\n"
                                                       "f 1/1/1 3/3/1 2/2/1\n");
    setenv("RTGI_GPU_BUDGET_MIB", "16", 1);
    rc = test_run_cli(&err, "render", "--quiet", "--size", "8x8", "--scene", obj, NULL); /* --quiet: no "added a default sun" */
    unsetenv("RTGI_GPU_BUDGET_MIB");
    test_expect_cli_error(rc, err, 1, "budget_quad.obj (1 triangles, 1 textures) needs 42 MiB", "budget of 16 MiB");
}

/* `--help` and the guide (docs/guide.md) come from (or agree with) the table. */
static void help_and_readme_list_every_setting(void **state)
{
    (void)state;
    char readme_path[512];
    snprintf(readme_path, sizeof readme_path, "%s/docs/guide.md", RTGI_SOURCE_DIR);
    char *readme = util_read_file(readme_path, NULL);
    assert_non_null(readme);
    Settings def;
    settings_default(&def);
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        /* The guide's settings table has a row "| `--option` | `family.field` | default | ...". */
        char row[256], value[64];
        settings_format(d, &def, value, sizeof value);
        snprintf(row, sizeof row, "| `%s` | `%s` | %s |", d->option, d->name, value);
        if (!strstr(readme, row))
            fail_msg("docs/guide.md lacks the settings row '%s'", row);
    }
    free(readme);
}

/* The technique table, the GiMode enum and the name list agree. */
static void technique_table_is_consistent(void **state)
{
    (void)state;
    assert_int_equal(gi_technique_count(), GI_MODE_COUNT);
    for (int i = 0; i < GI_MODE_COUNT; i++) {
        const GiTechnique *t = gi_techniques[i];
        assert_non_null(gi_technique_names()[i]);
        assert_string_equal(t->name, gi_technique_names()[i]);
        assert_int_equal(gi_technique_find(t->name), i);
        assert_non_null(t->needs);
        assert_non_null(t->summary);
        if (i != GI_NONE) {
            assert_non_null(t->create);
            assert_non_null(t->run);
            assert_non_null(t->destroy);
            assert_non_null(t->resize);
        }
    }
    assert_null(gi_technique_names()[GI_MODE_COUNT]);
    assert_string_equal(gi_techniques[GI_VPL_SLC]->name, "vpl-slc");
    assert_string_equal(gi_techniques[GI_RSM_INTERP]->name, "rsm-interp");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(technique_table_is_consistent),
        cmocka_unit_test(every_setting_has_one_name),
        cmocka_unit_test(every_setting_round_trips),
        cmocka_unit_test(old_spellings_still_parse),
        cmocka_unit_test(out_of_range_is_rejected_by_both),
        cmocka_unit_test(bad_scene_settings),
        cmocka_unit_test(help_and_readme_list_every_setting),
    };
    return cmocka_run_group_tests_name("settings", tests, NULL, NULL);
}
