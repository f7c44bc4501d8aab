/* view_panel.c — see view_panel.h. */
#include "ui/view_panel.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/log.h"
#include "base/util.h"
#include "gl/shader.h"
#include "ui/ui.h"
#include "ui/view_anim.h"
#include "ui/view_render.h"

static const char *const k_shadow_names[] = {"none", "hard", "pcf", "pcss"};
static const char *const k_ab_names[] = {"frame", "reference", "split", "difference"};

/* ---- Cost ------------------------------------------------------------------ */







/* ---- Bookkeeping ---------------------------------------------------------- */





/* ---- Window capture ----------------------------------------------------------- */

/* The window's back buffer as shown (panel included), before the swap. */
bool view_save_window(View *v, const char *path, int fw, int fh)
{
    uint8_t *rgb = malloc(3 * (size_t)fw * fh), *row = malloc(3 * (size_t)fw);
    bool allocated = rgb && row, ok = allocated;
    if (ok) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, fw, fh, GL_RGB, GL_UNSIGNED_BYTE, rgb);
        for (int y = 0; y < fh / 2; y++) { /* GL rows are bottom-up */
            memcpy(row, rgb + 3 * (size_t)y * fw, 3 * (size_t)fw);
            memcpy(rgb + 3 * (size_t)y * fw, rgb + 3 * (size_t)(fh - 1 - y) * fw, 3 * (size_t)fw);
            memcpy(rgb + 3 * (size_t)(fh - 1 - y) * fw, row, 3 * (size_t)fw);
        }
        util_ensure_parent_dir(path);
        ok = image_write_png8(path, fw, fh, rgb);
    }
    free(rgb);
    free(row);
    if (ok)
        view_status(v->status, false, "wrote %s", path);
    else if (!allocated)
        view_status(v->status, true, "%s: out of memory for the window capture", path);
    /* else image_write_png8 logged why, and the log hook put it on the panel */
    return ok;
}

/* ---- The panel ------------------------------------------------------------- */

/* One row of the settings table as a widget with its range; true when a
 * change is committed (sliders: on release). */
static bool setting_widget(View *v, const SettingDesc *d)
{
    void *field = (char *)&v->edit + d->offset;
    char label[96], tip[320], range[64] = "";
    snprintf(label, sizeof label, "%s##%s", d->field, d->option);
    bool commit = false;
    switch (d->type) {
    case VALUE_INT: {
        bool logarithmic = d->max / fmax(d->min, 1.0) > 1000;
        ui_slider_int(label, (int *)field, (int)d->min, (int)d->max, logarithmic);
        commit = ui_item_deactivated_after_edit();
        snprintf(range, sizeof range, " [%.0f..%.0f]", d->min, d->max);
        break;
    }
    case VALUE_UINT: {
        int x = (int)*(unsigned *)field;
        ui_slider_int(label, &x, (int)d->min, (int)fmin(d->max, 2147483647.0), true);
        *(unsigned *)field = (unsigned)x;
        commit = ui_item_deactivated_after_edit();
        snprintf(range, sizeof range, " [%.0f..%.0f]", d->min, d->max);
        break;
    }
    case VALUE_FLOAT: {
        bool logarithmic = d->min > 0 ? d->max / d->min > 1000 : d->max > 100;
        ui_slider_float(label, (float *)field, (float)d->min, (float)d->max, logarithmic, "%.4g");
        commit = ui_item_deactivated_after_edit();
        snprintf(range, sizeof range, " [%.6g..%.6g]", d->min, d->max);
        break;
    }
    case VALUE_BOOL:
    case VALUE_FLAG:
        commit = ui_checkbox(label, (bool *)field);
        break;
    case VALUE_CHOICE: {
        int count = 0;
        while (d->choices[count])
            count++;
        commit = ui_combo(label, (int *)field, d->choices, count);
        break;
    }
    case VALUE_PAIR: {
        int pair[2] = {*(int *)field, *(int *)((char *)&v->edit + d->offset2)};
        ui_slider_int2(label, pair, (int)d->min, (int)d->max);
        *(int *)field = pair[0];
        *(int *)((char *)&v->edit + d->offset2) = pair[1];
        commit = ui_item_deactivated_after_edit();
        snprintf(range, sizeof range, " [%.0f..%.0f] each", d->min, d->max);
        break;
    }
    case VALUE_DOUBLE: /* command options' types: no settings row has them */
    case VALUE_SIZE:
    case VALUE_TEXT:
        break;
    }
    snprintf(tip, sizeof tip, "%s%s\n%s, scene key %s", d->help, range, d->option, d->name);
    ui_tooltip(tip);
    return commit;
}

static void technique_section(View *v)
{
    char labels[GI_MODE_COUNT][96];
    const char *items[GI_MODE_COUNT];
    for (int i = 0; i < GI_MODE_COUNT; i++) {
        double ms = view_estimate_ms(v, i);
        if (view_gi_is_slow(v, i))
            snprintf(labels[i], sizeof labels[i], "%s  (slow: ~%.1f s/frame)", gi_techniques[i]->name, ms / 1e3);
        else
            snprintf(labels[i], sizeof labels[i], "%s", gi_techniques[i]->name);
        items[i] = labels[i];
    }
    int gi = (int)v->settings.gi;
    if (ui_combo("GI (G)", &gi, items, GI_MODE_COUNT))
        view_select_gi(v, gi, false);
    ui_tooltip(gi_techniques[v->settings.gi]->summary);
    if (v->pending_gi >= 0) {
        ui_text_colored(1.f, 0.7f, 0.2f, "%s: ~%.1f s per frame at %dx%d", gi_techniques[v->pending_gi]->name,
                        view_estimate_ms(v, v->pending_gi) / 1e3, v->settings.width, v->settings.height);
        if (ui_button("Switch anyway"))
            view_select_gi(v, v->pending_gi, true);
        ui_same_line();
        if (ui_button("Cancel"))
            view_cancel_gi(v);
    }
    int shadow = (int)v->settings.shadow;
    if (ui_combo("shadows (1-4)", &shadow, k_shadow_names, 4))
        v->settings.shadow = (ShadowMode)shadow;
    /* Exposure is live: renderer_apply remakes nothing for it. */
    ui_slider_float("exposure (+/-)", &v->settings.exposure, 1e-3f, 1e3f, true, "%.3g");
    bool fxaa = v->settings.aa == AA_FXAA;
    if (ui_checkbox("FXAA (F)", &fxaa))
        v->settings.aa = fxaa ? AA_FXAA : AA_NONE;
    int ssaa = renderer_ssaa(&v->settings);
    ui_slider_int("supersampling", &ssaa, 1, 4, false);
    if (ui_item_deactivated_after_edit())
        v->settings.ssaa = ssaa;
}

static void timings_section(View *v)
{
    const ViewStats *m = &v->stats;
    /* On a software rasterizer the passes' times are wall times fenced by
     * glFinish (see gl_renderer_is_software), as `render --timings` counts them. */
    ui_text("frame %.1f ms, passes %.1f ms (%s)", m->frame_ms, m->gpu_ms, m->pass_wall ? "wall" : "GPU");
    ui_text("GPU memory %.1f MiB", render_mib(render_memory_total(&m->memory)));
    ui_text("  lights %.1f, GI %.1f,", render_mib(m->memory.lights), render_mib(m->memory.gi));
    ui_text("  frame %.1f, scene %.1f", render_mib(m->memory.frame), render_mib(m->memory.scene));
    const char *headers[] = {"pass", m->pass_wall ? "wall ms" : "GPU ms"};
    if (m->pass_count > 0 && ui_table_begin("passes", 2, headers)) {
        for (int i = 0; i < m->pass_count; i++) {
            char ms[32];
            snprintf(ms, sizeof ms, "%.2f", m->pass_ms[i]);
            const char *cells[2] = {m->pass_name[i], ms};
            ui_table_row(cells, 2);
        }
        ui_table_end();
    }
    float hi = 0;
    for (int i = 0; i < m->history_count; i++)
        hi = fmaxf(hi, m->history[i]);
    char overlay[64];
    snprintf(overlay, sizeof overlay, "frame ms (max %.1f)", (double)hi);
    int start = m->history_count < VIEW_HISTORY ? 0 : m->history_next;
    ui_plot_lines("##history", m->history, m->history_count, start, overlay, 0.f, hi * 1.1f + 1e-3f, 60.f);
}

static void settings_section(View *v)
{
    const char *group = NULL;
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        if (!group || strcmp(group, d->family)) {
            group = d->family;
            ui_separator();
            ui_text("%s", group);
        }
        if (setting_widget(v, d)) {
            v->settings.set.shadow = v->edit.shadow;
            v->settings.set.gi = v->edit.gi;
        }
    }
}

static void camera_section(View *v)
{
    const Camera *c = &v->camera;
    ui_text("position %.3f %.3f %.3f", (double)c->position[0], (double)c->position[1], (double)c->position[2]);
    ui_text("target   %.3f %.3f %.3f", (double)(c->position[0] + c->forward[0]),
            (double)(c->position[1] + c->forward[1]), (double)(c->position[2] + c->forward[2]));
    if (ui_button("Copy as scene JSON")) {
        char json[256];
        view_camera_json(v, json, sizeof json);
        ui_set_clipboard(json);
        printf("%s\n", json);
        fflush(stdout);
        view_status(v->status, false, "camera copied to the clipboard (and printed on stdout)");
    }
    ui_slider_float("speed m/s", &v->speed, 0.01f, 100.f, true, "%.3g");
}

void view_ask_reload(View *v)
{
    /* Set here, on the window's thread, which alone sets it: the render
     * thread reads it after the request that follows. */
    if (!shader_directory()) {
        char dir[1024];
        snprintf(dir, sizeof dir, "%s/shaders", RTGI_SOURCE_DIR);
        struct stat st;
        if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode))
            shader_set_directory(dir);
    }
    v->jobs |= VIEW_JOB_RELOAD;
}



/* The heat map's colours at 0, 1/3, 2/3 and 1 of its scale (ab_view.frag's
 * heat(): black, red, yellow, white, linear between). */
static const float k_heat_stops[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}};

void view_live_text(const View *v, char *out, size_t cap)
{
    live_reference_text(&v->live, out, cap);
}

static void live_section(View *v)
{
    ui_checkbox("live reference (path tracer)", &v->live_wanted);
    ui_tooltip("the reference path tracer converging in the background on this camera and the scene's lights, "
               "at the image's size, shown by the A/B view; a camera, light or size change restarts it");
    if (!v->live_wanted)
        return;
    char line[160];
    view_live_text(v, line, sizeof line);
    ui_text_wrapped("%s", line);
    if (v->live.spp > 0 && v->live.relmse_compare >= 0)
        ui_text("relMSE against --compare %.3g", v->live.relmse_compare);
}

static void compare_section(View *v)
{
    AbView *ab = v->ab;
    int mode = (int)ab->mode;
    if (ui_combo("view (C)", &mode, k_ab_names, AB_MODE_COUNT))
        ab->mode = (AbMode)mode;
    if (ab->mode == AB_SPLIT)
        ui_slider_float("split", &ab->split, 0.f, 1.f, false, "%.2f");
    if (ab->mode == AB_DIFFERENCE) {
        ui_checkbox("auto scale", &ab->diff_auto);
        ui_tooltip("full heat at the 99th percentile of this frame's max-channel |frame - reference| x exposure");
        if (!ab->diff_auto)
            ui_slider_float("full heat at", &ab->diff_scale, 1e-4f, 10.f, true, "%.4g");
        else if (v->ab_auto_scale <= 0)
            ui_text("(measuring the difference...)");
        char labels[4][16];
        view_heat_labels(view_heat_scale(v), labels);
        const char *const names[4] = {labels[0], labels[1], labels[2], labels[3]};
        ui_color_bar("##heat", k_heat_stops, 4, names, 4, 14.f);
    }
    if (ui_button("Measure RMSE"))
        v->jobs |= VIEW_JOB_RMSE;
    ui_same_line();
    if (!ab->reference.rgb)
        ui_text("(no reference yet: the live one's first pass)");
    else if (ab->reference.width != v->settings.width || ab->reference.height != v->settings.height)
        ui_text("reference %dx%d: stretched, no RMSE", ab->reference.width, ab->reference.height);
    else if (ab->display)
        ui_text("PNG reference: no RMSE (use .pfm or .exr)");
    else if (v->ab_rmse >= 0)
        ui_text("RMSE %.5g (radiance)", v->ab_rmse);
    else
        ui_text("(radiance)"); /* the next header below the button, not beside it */
}

static void capture_section(View *v)
{
    ui_input_text("image", v->shot_path, sizeof v->shot_path);
    ui_tooltip(".png: the image as shown; .pfm or .exr (OpenEXR; --half: half floats): linear radiance");
    ui_same_line();
    if (ui_button("Save (P)"))
        v->jobs |= VIEW_JOB_SAVE;
    ui_input_text("window", v->window_path, sizeof v->window_path);
    ui_same_line();
    if (ui_button("Save (Shift-P)"))
        v->window_shot = true;
    if (ui_button("Reload shaders (F5)"))
        view_ask_reload(v);
    const char *dir = shader_directory();
    ui_same_line();
    ui_text("from %s", dir ? dir : "(embedded)");
}


void view_busy_draw(const View *v)
{
    char text[96];
    view_busy_text(v, text, sizeof text);
    if (text[0])
        ui_overlay_text("##busy", 8.f, 8.f, text);
}

void view_panel_draw(View *v, float x, float h)
{
    if (!v->show_panel)
        return;
    if (!ui_panel_begin("rtgi (H hides)", &v->show_panel, x, 0.f, (float)VIEW_PANEL_WIDTH, h)) {
        ui_window_end();
        return;
    }
    ui_text("%s  %dx%d", v->scene->source, v->settings.width, v->settings.height);
    char status[sizeof v->status->text];
    bool error;
    view_status_get(v->status, status, sizeof status, &error);
    if (status[0]) {
        if (error)
            ui_text_colored(1.f, 0.35f, 0.3f, "%s", status);
        else
            ui_text_wrapped("%s", status);
    }
    char busy[96];
    view_busy_text(v, busy, sizeof busy);
    if (busy[0])
        ui_text_colored(1.f, 0.8f, 0.3f, "%s", busy);
    /* With a reference, comparing is what the window is for: its controls
     * and the heat map's colour bar come first. */
    if (ui_header("Reference", true))
        live_section(v);
    if (v->ab && ui_header("Compare (A/B)", true))
        compare_section(v);
    if (ui_header("Technique", true))
        technique_section(v);
    view_anim_panel(v); /* Animation, Lights (src/ui/view_anim.c) */
    if (ui_header("Timings (T prints them)", true))
        timings_section(v);
    if (ui_header("Settings", false))
        settings_section(v);
    if (ui_header("Camera", false))
        camera_section(v);
    if (ui_header("Capture & shaders", false))
        capture_section(v);
    if (ui_header("Keys", false)) {
        ui_text_wrapped("WASD move, Q/E down/up, Shift faster, left-drag look, R reset camera; 1-4 shadows; "
                        "G/Shift-G technique (slow ones ask first); +/- exposure; F FXAA; C A/B view; "
                        "T print timings; P save image, Shift-P save window; F5 reload shaders; "
                        "H panel; Esc quit.");
        ui_text_wrapped("Animation: Space play/pause (the time slider scrubs). Lights: arrows move the light "
                        "across the view, Page Up/Down raise/lower it (a sun: arrows turn it), L next light; its "
                        "power in Lights.");
    }
    ui_window_end();
}
