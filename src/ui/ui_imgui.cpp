// ui_imgui.cpp — ui.h over Dear ImGui 1.86 (Debian libimgui-dev). The only
// C++ file: everything else about the window stays in C.
//
// The OpenGL 3 back-end brings its own loader (imgui_impl_opengl3_loader.h,
// "imgl3w": dlopen of libGL.so.1 and glXGetProcAddress into its own table of
// function pointers), so it defines no GL symbols and coexists with libepoxy,
// which rtgi uses everywhere else; the back-end saves and restores the GL
// state it touches.
#include "ui/ui.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

extern "C" {
#include "base/log.h"
}

static GLFWwindow *g_window;

/* Dear ImGui uses what it allocates without checking it, so a failed
 * allocation cannot be handed back to it: the command ends here with one
 * line and exit status 1 (the one exit outside main; no output is being
 * written while the panel is built or drawn) instead of a crash inside the
 * library. _exit, not exit: the render thread may be inside the GL driver,
 * whose exit handlers must not run under it; stdio is flushed first. */
static long g_alloc_fail_at; /* RTGI_FAIL_UI_ALLOC=k: the k-th allocation fails (fault injection) */

static void *ui_alloc(size_t n, void *user)
{
    (void)user;
    bool refuse = g_alloc_fail_at > 0 && --g_alloc_fail_at == 0;
    void *p = refuse ? NULL : malloc(n);
    if (!p && n) {
        log_error("ui", "out of memory (%zu bytes) in Dear ImGui, which cannot go on without it; the window ends", n);
        fflush(NULL);
        _exit(1);
    }
    return p;
}

static void ui_free(void *p, void *user)
{
    (void)user;
    free(p);
}

extern "C" bool ui_create(GLFWwindow *window)
{
    IMGUI_CHECKVERSION();
    const char *fail_at = getenv("RTGI_FAIL_UI_ALLOC");
    g_alloc_fail_at = fail_at ? strtol(fail_at, NULL, 10) : 0;
    ImGui::SetAllocatorFunctions(ui_alloc, ui_free, nullptr);
    ImGui::CreateContext();
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = nullptr; // no imgui.ini beside the user's files
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.f; /* opaque: the frame's noise stays out of the panel */
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
        log_error("ui", "Dear ImGui: cannot attach to the GLFW window");
        ImGui::DestroyContext();
        return false;
    }
    if (!ImGui_ImplOpenGL3_Init("#version 450 core")) {
        log_error("ui", "Dear ImGui: the OpenGL 3 back-end cannot load GL (libGL.so.1)");
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        return false;
    }
    g_window = window;
    return true;
}

extern "C" void ui_destroy(void)
{
    if (!g_window)
        return;
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    g_window = nullptr;
}

extern "C" bool ui_wants_keyboard(void) { return g_window && ImGui::GetIO().WantCaptureKeyboard; }
extern "C" bool ui_wants_mouse(void) { return g_window && ImGui::GetIO().WantCaptureMouse; }

extern "C" void ui_frame_begin(void)
{
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

extern "C" void ui_frame_end(void)
{
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

extern "C" bool ui_panel_begin(const char *title, bool *open, float x, float y, float w, float h)
{
    ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, h), ImGuiCond_Always);
    return ImGui::Begin(title, open,
                        ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                            ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus);
}

extern "C" void ui_overlay_text(const char *id, float x, float y, const char *text)
{
    ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.7f);
    if (ImGui::Begin(id, nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_AlwaysAutoResize |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                         ImGuiWindowFlags_NoNav))
        ImGui::TextUnformatted(text);
    ImGui::End();
}

extern "C" void ui_color_bar(const char *id, const float (*stops)[3], int stop_count, const char *const *labels,
                             int label_count, float height)
{
    ImGui::PushID(id);
    ImDrawList *draw = ImGui::GetWindowDrawList();
    ImVec2 p = ImGui::GetCursorScreenPos();
    float w = ImGui::GetContentRegionAvail().x;
    for (int i = 0; i + 1 < stop_count; i++) {
        float x0 = p.x + w * (float)i / (float)(stop_count - 1), x1 = p.x + w * (float)(i + 1) / (float)(stop_count - 1);
        ImU32 a = ImGui::ColorConvertFloat4ToU32(ImVec4(stops[i][0], stops[i][1], stops[i][2], 1.f));
        ImU32 b = ImGui::ColorConvertFloat4ToU32(ImVec4(stops[i + 1][0], stops[i + 1][1], stops[i + 1][2], 1.f));
        draw->AddRectFilledMultiColor(ImVec2(x0, p.y), ImVec2(x1, p.y + height), a, b, b, a);
    }
    ImGui::Dummy(ImVec2(w, height));
    float y = ImGui::GetCursorPosY(), x = ImGui::GetCursorPosX();
    for (int i = 0; i < label_count; i++) {
        float tw = ImGui::CalcTextSize(labels[i]).x;
        float at = label_count > 1 ? w * (float)i / (float)(label_count - 1) : 0.f;
        at = at - 0.5f * tw; /* centred under its place, kept inside the bar */
        if (at < 0.f)
            at = 0.f;
        if (at > w - tw)
            at = w - tw;
        ImGui::SetCursorPos(ImVec2(x + at, y));
        ImGui::TextUnformatted(labels[i]);
    }
    ImGui::PopID();
}

extern "C" void ui_window_end(void) { ImGui::End(); }

extern "C" bool ui_header(const char *label, bool open_by_default)
{
    return ImGui::CollapsingHeader(label, open_by_default ? ImGuiTreeNodeFlags_DefaultOpen : 0);
}

extern "C" void ui_text(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    ImGui::TextV(fmt, ap);
    va_end(ap);
}

extern "C" void ui_text_colored(float r, float g, float b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    ImGui::TextColoredV(ImVec4(r, g, b, 1.f), fmt, ap);
    va_end(ap);
}

extern "C" void ui_text_wrapped(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    ImGui::TextWrappedV(fmt, ap);
    va_end(ap);
}

extern "C" void ui_tooltip(const char *text)
{
    if (text && ImGui::IsItemHovered())
        ImGui::SetTooltip("%s", text);
}

extern "C" void ui_separator(void) { ImGui::Separator(); }
extern "C" void ui_same_line(void) { ImGui::SameLine(); }
extern "C" void ui_push_id(int id) { ImGui::PushID(id); }
extern "C" void ui_pop_id(void) { ImGui::PopID(); }
extern "C" bool ui_button(const char *label) { return ImGui::Button(label); }
extern "C" bool ui_checkbox(const char *label, bool *v) { return ImGui::Checkbox(label, v); }

extern "C" bool ui_combo(const char *label, int *index, const char *const *items, int count)
{
    return ImGui::Combo(label, index, items, count);
}

extern "C" bool ui_slider_float(const char *label, float *v, float lo, float hi, bool logarithmic, const char *format)
{
    return ImGui::SliderFloat(label, v, lo, hi, format ? format : "%.4g",
                              logarithmic ? ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoRoundToFormat : 0);
}

extern "C" bool ui_slider_int(const char *label, int *v, int lo, int hi, bool logarithmic)
{
    return ImGui::SliderInt(label, v, lo, hi, "%d", logarithmic ? ImGuiSliderFlags_Logarithmic : 0);
}

extern "C" bool ui_slider_int2(const char *label, int v[2], int lo, int hi)
{
    return ImGui::SliderInt2(label, v, lo, hi);
}

extern "C" bool ui_input_text(const char *label, char *buf, size_t cap)
{
    return ImGui::InputText(label, buf, cap);
}

extern "C" bool ui_item_deactivated_after_edit(void) { return ImGui::IsItemDeactivatedAfterEdit(); }

extern "C" bool ui_table_begin(const char *id, int columns, const char *const *headers)
{
    if (!ImGui::BeginTable(id, columns, ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit))
        return false;
    for (int i = 0; i < columns; i++)
        ImGui::TableSetupColumn(headers[i]);
    ImGui::TableHeadersRow();
    return true;
}

extern "C" void ui_table_row(const char *const *cells, int columns)
{
    ImGui::TableNextRow();
    for (int i = 0; i < columns; i++) {
        ImGui::TableSetColumnIndex(i);
        ImGui::TextUnformatted(cells[i]);
    }
}

extern "C" void ui_table_end(void) { ImGui::EndTable(); }

extern "C" void ui_plot_lines(const char *label, const float *values, int count, int offset, const char *overlay,
                              float lo, float hi, float height)
{
    ImGui::PlotLines(label, values, count, offset, overlay, lo, hi, ImVec2(0, height));
}

extern "C" void ui_set_clipboard(const char *text)
{
    if (g_window)
        glfwSetClipboardString(g_window, text);
}
