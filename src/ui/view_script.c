/* view_script.c — see view_script.h. */
#include "ui/view_script.h"

#include <stdio.h>
#include <stdlib.h>

#include "shader.h"

static void script_path(const ViewScript *t, const char *name, char *out, size_t cap)
{
    snprintf(out, cap, "%s/%s", t->dir, name);
}

bool view_script_step(ViewScript *t, View *v, int frame, int fw, int fh)
{
    Renderer *r = v->renderer;
    char path[1024];
    switch (frame) {
    case 0: /* the window shows the frame alone until the A/B steps */
        if (v->ab)
            v->ab->mode = AB_FRAME;
        gpu_timer_reset(&r->timer); /* the timings table of frames 1-2, after the cold first one */
        break;
    case 1: { /* what "Copy as scene JSON" copies */
        char json[256];
        view_camera_json(v, json, sizeof json);
        printf("ui-test: camera {%s}\n", json);
        break;
    }
    case 2: /* the panel's timings table; then exposure through the panel's path: live, nothing remade */
        view_take_pass_table(v);
        printf("ui-test: timings gi %s, %s ms, %d frames:", gi_techniques[r->settings.gi]->name,
               v->pass_wall ? "wall" : "gpu", r->timer.frames);
        for (int i = 0; i < v->pass_count; i++)
            printf(" %s=%.3f", v->pass_name[i], v->pass_ms[i]);
        printf("\n");
        t->links = shader_link_count();
        t->remakes = r->remakes;
        v->settings.exposure *= 2.f;
        v->dirty = true;
        break;
    case 4:
        printf("ui-test: exposure x2: program links +%d, renderer remakes +%d\n", shader_link_count() - t->links,
               r->remakes - t->remakes);
        script_path(t, "window_panel.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        v->show_panel = false;
        break;
    case 6:
        script_path(t, "window_nopanel.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        script_path(t, "shot.png", path, sizeof path);
        view_save_image(v, path);
        script_path(t, "shot.pfm", path, sizeof path);
        view_save_image(v, path);
        script_path(t, "shot.exr", path, sizeof path);
        view_save_image(v, path);
        v->show_panel = true;
        break;
    case 7: /* the G key's path into the next technique */
        t->remakes = r->remakes;
        view_cycle_gi(v, 1);
        printf("ui-test: G: gi %s, pending %s, estimate %.3g ms, slow above %.3g ms\n",
               gi_techniques[v->settings.gi]->name, v->pending_gi >= 0 ? gi_techniques[v->pending_gi]->name : "none",
               view_estimate_ms(v, v->pending_gi >= 0 ? v->pending_gi : (int)v->settings.gi), v->slow_ms);
        break;
    case 9: /* its confirming click */
        if (v->pending_gi >= 0)
            view_select_gi(v, v->pending_gi, true);
        printf("ui-test: confirmed: gi %s\n", gi_techniques[v->settings.gi]->name);
        break;
    case 10:
        v->show_panel = false;
        break;
    case 11: {
        printf("ui-test: technique switch: renderer remakes +%d\n", r->remakes - t->remakes);
        script_path(t, "before_reload.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        /* Hot reload with a shader broken on disk (the test names it): the
         * error reaches the panel and the previous program stays. */
        const char *broken = getenv("RTGI_UI_TEST_BREAK_SHADER");
        FILE *f = broken ? fopen(broken, "a") : NULL;
        if (f) {
            fputs("\n#error broken by the ui test\n", f);
            fclose(f);
        }
        v->reload = true;
        break;
    }
    case 12:
        printf("ui-test: reload: %s: %s\n", v->status_error ? "failed" : "ok", v->status);
        script_path(t, "after_reload.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        if (!v->ab)
            return false;
        v->ab->mode = AB_REFERENCE;
        break;
    case 14:
        script_path(t, "ab_reference.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        v->ab->mode = AB_DIFFERENCE;
        v->ab->diff_scale = 0.05f;
        break;
    case 16:
        script_path(t, "ab_difference.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        printf("ui-test: rmse %.6g\n", ab_view_rmse(v->ab, r));
        v->ab->mode = AB_SPLIT;
        v->ab->split = 0.5f;
        break;
    case 18:
        script_path(t, "ab_split.png", path, sizeof path);
        view_save_window(v, path, fw, fh);
        return false;
    default:
        break;
    }
    fflush(stdout);
    return true;
}
