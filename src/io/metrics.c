#include "io/metrics.h"
#include "base/log.h"

#include "base/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static bool counts(const uint8_t *mask, size_t i) { return !mask || mask[i]; }

/* Image-sized scratch: NULL after logging the size, and counted so that
 * the caller can tell a metric that ran out of memory (NaN) from one whose
 * input was NaN. */
static int g_alloc_failures;

int metric_alloc_failures(void) { return g_alloc_failures; }

static float *fbuf(size_t n)
{
    float *p = util_malloc("compare", "metric scratch", n, sizeof(float));
    if (!p)
        g_alloc_failures++;
    return p;
}

double metric_rmse(const ImageF *t, const ImageF *r, const uint8_t *mask, float *map)
{
    double sum = 0;
    size_t n = 0, np = (size_t)t->width * t->height;
    for (size_t i = 0; i < np; i++) {
        double e = 0;
        for (int c = 0; c < 3; c++) {
            double d = (double)t->rgb[3 * i + c] - r->rgb[3 * i + c];
            e += d * d;
        }
        if (map)
            map[i] = (float)sqrt(e / 3);
        if (counts(mask, i)) {
            sum += e;
            n += 3;
        }
    }
    return n ? sqrt(sum / n) : 0.0;
}

double metric_relmse(const ImageF *t, const ImageF *r, const uint8_t *mask, float *map)
{
    double sum = 0;
    size_t n = 0, np = (size_t)t->width * t->height;
    for (size_t i = 0; i < np; i++) {
        double e = 0;
        for (int c = 0; c < 3; c++) {
            double d = (double)t->rgb[3 * i + c] - r->rgb[3 * i + c], ref = r->rgb[3 * i + c];
            e += d * d / (ref * ref + 0.01);
        }
        if (map)
            map[i] = (float)(e / 3);
        if (counts(mask, i)) {
            sum += e;
            n += 3;
        }
    }
    return n ? sum / n : 0.0;
}

/* ------------------------------------------------------------ filtering */

/* Separable convolution of a w×h float plane with a 1D kernel of radius r
 * along x then (kernel ky) along y; borders replicate. */
static bool convolve_sep(const float *in, float *out, int w, int h, const float *kx, const float *ky, int r)
{
    float *tmp = fbuf((size_t)w * h);
    if (!tmp)
        return false;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double s = 0;
            for (int k = -r; k <= r; k++) {
                int xx = x + k < 0 ? 0 : (x + k >= w ? w - 1 : x + k);
                s += kx[k + r] * in[(size_t)y * w + xx];
            }
            tmp[(size_t)y * w + x] = (float)s;
        }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double s = 0;
            for (int k = -r; k <= r; k++) {
                int yy = y + k < 0 ? 0 : (y + k >= h ? h - 1 : y + k);
                s += ky[k + r] * tmp[(size_t)yy * w + x];
            }
            out[(size_t)y * w + x] = (float)s;
        }
    free(tmp);
    return true;
}

/* Display-encoded (× exposure, clamped, sRGB) copy of a linear image. */
static float *display(const ImageF *img, float exposure)
{
    size_t n = (size_t)img->width * img->height * 3;
    float *d = fbuf(n);
    for (size_t i = 0; d && i < n; i++)
        d[i] = srgb_encode(img->rgb[i] * exposure);
    return d;
}

/* ------------------------------------------------------------------ SSIM */

double metric_ssim(const ImageF *t, const ImageF *r, float exposure, const uint8_t *mask, float *map)
{
    int w = t->width, h = t->height;
    size_t np = (size_t)w * h;
    float *dt = display(t, exposure), *dr = display(r, exposure);
    float *planes[5];
    bool ok = dt && dr;
    for (int k = 0; k < 5; k++)
        ok = (planes[k] = ok ? fbuf(np) : NULL) != NULL;
    float *mu_a = ok ? fbuf(np) : NULL, *mu_b = mu_a ? fbuf(np) : NULL;
    float *saa = mu_b ? fbuf(np) : NULL, *sbb = saa ? fbuf(np) : NULL, *sab = sbb ? fbuf(np) : NULL;
    ok = sab != NULL;
    double sum = 0;
    size_t n = 0;
    if (!ok)
        goto done;
    float *a = planes[0], *b = planes[1];
    for (size_t i = 0; i < np; i++) {
        a[i] = luminance(dt + 3 * i);
        b[i] = luminance(dr + 3 * i);
    }
    const int rad = 5;
    float g[11];
    double gs = 0;
    for (int k = -rad; k <= rad; k++)
        gs += g[k + rad] = expf(-(float)(k * k) / (2.f * 1.5f * 1.5f));
    for (int k = 0; k < 11; k++)
        g[k] /= (float)gs;
    ok = convolve_sep(a, mu_a, w, h, g, g, rad) && convolve_sep(b, mu_b, w, h, g, g, rad);
    for (size_t i = 0; i < np; i++) {
        planes[2][i] = a[i] * a[i];
        planes[3][i] = b[i] * b[i];
        planes[4][i] = a[i] * b[i];
    }
    ok = ok && convolve_sep(planes[2], saa, w, h, g, g, rad) && convolve_sep(planes[3], sbb, w, h, g, g, rad) &&
         convolve_sep(planes[4], sab, w, h, g, g, rad);
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    for (size_t i = 0; ok && i < np; i++) {
        double ma = mu_a[i], mb = mu_b[i];
        double va = saa[i] - ma * ma, vb = sbb[i] - mb * mb, cov = sab[i] - ma * mb;
        double s = ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
        if (map)
            map[i] = (float)s;
        if (counts(mask, i)) {
            sum += s;
            n++;
        }
    }
done:
    for (int k = 0; k < 5; k++)
        free(planes[k]);
    free(mu_a);
    free(mu_b);
    free(saa);
    free(sbb);
    free(sab);
    free(dt);
    free(dr);
    if (!ok)
        return NAN;
    return n ? sum / n : 1.0;
}

/* ------------------------------------------------------------------ FLIP */

/* D65 white and sRGB ↔ XYZ (linear). */
static const double k_white[3] = {0.950428545, 1.0, 1.088900371};

static void lin_to_xyz(const double *c, double *x)
{
    x[0] = 0.4123907993 * c[0] + 0.3575843394 * c[1] + 0.1804807884 * c[2];
    x[1] = 0.2126390059 * c[0] + 0.7151686788 * c[1] + 0.0721923154 * c[2];
    x[2] = 0.0193308187 * c[0] + 0.1191947798 * c[1] + 0.9505321522 * c[2];
}

static void xyz_to_lin(const double *x, double *c)
{
    c[0] = 3.241003275 * x[0] - 1.537398934 * x[1] - 0.498615861 * x[2];
    c[1] = -0.969224334 * x[0] + 1.875930071 * x[1] + 0.041554224 * x[2];
    c[2] = 0.055639423 * x[0] - 0.204011202 * x[1] + 1.057148933 * x[2];
}

/* Linearised CIELAB without the cube root (the paper's YCxCz). */
static void xyz_to_ycxcz(const double *x, double *o)
{
    double xn = x[0] / k_white[0], yn = x[1] / k_white[1], zn = x[2] / k_white[2];
    o[0] = 116 * yn - 16;
    o[1] = 500 * (xn - yn);
    o[2] = 200 * (yn - zn);
}

static void ycxcz_to_xyz(const double *o, double *x)
{
    double y = (o[0] + 16) / 116;
    x[0] = (y + o[1] / 500) * k_white[0];
    x[1] = y * k_white[1];
    x[2] = (y - o[2] / 200) * k_white[2];
}

static double lab_f(double t)
{
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
}

/* Hunt-adjusted CIELAB of a linear RGB colour. */
static void lin_to_hunt_lab(const double *c, double *lab)
{
    double x[3];
    lin_to_xyz(c, x);
    double fx = lab_f(x[0] / k_white[0]), fy = lab_f(x[1] / k_white[1]), fz = lab_f(x[2] / k_white[2]);
    lab[0] = 116 * fy - 16;
    lab[1] = 0.01 * lab[0] * 500 * (fx - fy);
    lab[2] = 0.01 * lab[0] * 200 * (fy - fz);
}

static double hyab(const double *a, const double *b)
{
    return fabs(a[0] - b[0]) + hypot(a[1] - b[1], a[2] - b[2]);
}

/* The CSF filter of one opponent channel as a sum of two separable
 * Gaussians: applies it to `in` into `out`. */
static bool csf_filter(const float *in, float *out, int w, int h, float ppd, double a1, double b1, double a2,
                       double b2)
{
    const double bmax = 0.04; /* largest b over all three channels sets the support */
    int r = (int)ceil(3 * sqrt(bmax / (2 * M_PI * M_PI)) * ppd);
    int n = 2 * r + 1;
    float *g1 = fbuf((size_t)n), *g2 = g1 ? fbuf((size_t)n) : NULL;
    if (!g2) {
        free(g1);
        return false;
    }
    double s1 = 0, s2 = 0;
    for (int k = -r; k <= r; k++) {
        double x = k / (double)ppd;
        g1[k + r] = (float)exp(-M_PI * M_PI * x * x / b1);
        g2[k + r] = (float)exp(-M_PI * M_PI * x * x / b2);
        s1 += g1[k + r];
        s2 += g2[k + r];
    }
    double c1 = a1 * sqrt(M_PI / b1), c2 = a2 * sqrt(M_PI / b2);
    double total = c1 * s1 * s1 + c2 * s2 * s2; /* sum of the 2D kernel */
    bool ok = convolve_sep(in, out, w, h, g1, g1, r);
    if (ok && c2 > 0) {
        float *tmp = fbuf((size_t)w * h);
        ok = tmp && convolve_sep(in, tmp, w, h, g2, g2, r);
        for (size_t i = 0; ok && i < (size_t)w * h; i++)
            out[i] = (float)((c1 * out[i] + c2 * tmp[i]) / total);
        free(tmp);
    } else if (ok) {
        for (size_t i = 0; i < (size_t)w * h; i++)
            out[i] = (float)(c1 * out[i] / total);
    }
    free(g1);
    free(g2);
    return ok;
}

/* Edge (first derivative) and point (second derivative) feature
 * magnitudes of the normalised achromatic plane y. */
static bool features(const float *y, int w, int h, float ppd, float *edge, float *point)
{
    double sd = 0.5 * 0.082 * ppd;
    int r = (int)ceil(3 * sd), n = 2 * r + 1;
    float *g = fbuf((size_t)n), *d1 = g ? fbuf((size_t)n) : NULL, *d2 = d1 ? fbuf((size_t)n) : NULL;
    if (!d2) {
        free(g);
        free(d1);
        return false;
    }
    double gs = 0, p1 = 0, m1 = 0, p2 = 0, m2 = 0;
    for (int k = -r; k <= r; k++) {
        double gv = exp(-(k * k) / (2 * sd * sd));
        g[k + r] = (float)gv;
        d1[k + r] = (float)(-k * gv);
        d2[k + r] = (float)((k * k) / (sd * sd) - 1) * (float)gv;
        gs += gv;
        if (d1[k + r] > 0) p1 += d1[k + r]; else m1 -= d1[k + r];
        if (d2[k + r] > 0) p2 += d2[k + r]; else m2 -= d2[k + r];
    }
    /* Positive weights sum to 1, negative to −1 (of the 2D kernel). */
    for (int k = 0; k < n; k++) {
        g[k] = (float)(g[k] / gs);
        d1[k] = (float)(d1[k] > 0 ? d1[k] / p1 : d1[k] / m1);
        d2[k] = (float)(d2[k] > 0 ? d2[k] / p2 : d2[k] / m2);
    }
    size_t np = (size_t)w * h;
    float *ex = fbuf(np), *ey = ex ? fbuf(np) : NULL;
    float *px = ey ? fbuf(np) : NULL, *py = px ? fbuf(np) : NULL;
    bool ok = py && convolve_sep(y, ex, w, h, d1, g, r) && convolve_sep(y, ey, w, h, g, d1, r) &&
              convolve_sep(y, px, w, h, d2, g, r) && convolve_sep(y, py, w, h, g, d2, r);
    for (size_t i = 0; ok && i < np; i++) {
        edge[i] = hypotf(ex[i], ey[i]);
        point[i] = hypotf(px[i], py[i]);
    }
    free(g);
    free(d1);
    free(d2);
    free(ex);
    free(ey);
    free(px);
    free(py);
    return ok;
}

double metric_flip(const ImageF *t, const ImageF *r, float exposure, float ppd, const uint8_t *mask, float *map)
{
    int w = t->width, h = t->height;
    size_t np = (size_t)w * h;
    const ImageF *imgs[2] = {r, t};
    float *opp[2][3] = {{0}}, *filt[2][3] = {{0}}, *edge[2] = {0}, *point[2] = {0};
    double sum = 0;
    size_t n = 0;
    bool ok = true;
    for (int k = 0; k < 2 && ok; k++) {
        float *disp = display(imgs[k], exposure);
        ok = disp != NULL;
        for (int c = 0; c < 3 && ok; c++)
            ok = (opp[k][c] = fbuf(np)) && (filt[k][c] = fbuf(np));
        for (size_t i = 0; ok && i < np; i++) {
            double lin[3], xyz[3], o[3];
            for (int c = 0; c < 3; c++)
                lin[c] = srgb_decode(disp[3 * i + c]);
            lin_to_xyz(lin, xyz);
            xyz_to_ycxcz(xyz, o);
            for (int c = 0; c < 3; c++)
                opp[k][c][i] = (float)o[c];
        }
        free(disp);
        ok = ok && csf_filter(opp[k][0], filt[k][0], w, h, ppd, 1.0, 0.0047, 0.0, 1e-5) &&
             csf_filter(opp[k][1], filt[k][1], w, h, ppd, 1.0, 0.0053, 0.0, 1e-5) &&
             csf_filter(opp[k][2], filt[k][2], w, h, ppd, 34.1, 0.04, 13.5, 0.025);
        float *ynorm = ok ? fbuf(np) : NULL;
        for (size_t i = 0; ynorm && i < np; i++)
            ynorm[i] = (opp[k][0][i] + 16.f) / 116.f;
        ok = ynorm && (edge[k] = fbuf(np)) && (point[k] = fbuf(np)) &&
             features(ynorm, w, h, ppd, edge[k], point[k]);
        free(ynorm);
    }
    if (!ok)
        goto done;
    const double qc = 0.7, qf = 0.5, pc = 0.4, pt = 0.95;
    double green[3] = {0, 1, 0}, blue[3] = {0, 0, 1}, lg[3], lb[3];
    lin_to_hunt_lab(green, lg);
    lin_to_hunt_lab(blue, lb);
    double cmax = pow(hyab(lg, lb), qc), pccmax = pc * cmax;
    for (size_t i = 0; i < np; i++) {
        double lab[2][3];
        for (int k = 0; k < 2; k++) {
            double o[3] = {filt[k][0][i], filt[k][1][i], filt[k][2][i]}, xyz[3], lin[3];
            ycxcz_to_xyz(o, xyz);
            xyz_to_lin(xyz, lin);
            for (int c = 0; c < 3; c++)
                lin[c] = lin[c] < 0 ? 0 : (lin[c] > 1 ? 1 : lin[c]);
            lin_to_hunt_lab(lin, lab[k]);
        }
        double de = pow(hyab(lab[0], lab[1]), qc);
        double dec = de < pccmax ? (pt / pccmax) * de : pt + (de - pccmax) / (cmax - pccmax) * (1 - pt);
        double df = fmax(fabs(edge[0][i] - edge[1][i]), fabs(point[0][i] - point[1][i]));
        df = pow(df / sqrt(2.0), qf);
        double f = pow(dec, 1 - df);
        if (map)
            map[i] = (float)f;
        if (counts(mask, i)) {
            sum += f;
            n++;
        }
    }
done:
    for (int k = 0; k < 2; k++) {
        for (int c = 0; c < 3; c++) {
            free(opp[k][c]);
            free(filt[k][c]);
        }
        free(edge[k]);
        free(point[k]);
    }
    if (!ok)
        return NAN;
    return n ? sum / n : 0.0;
}

/* ------------------------------------------------------------ heat maps */

/* Approximate magma, 9 stops: v in [0,1] (clamped; NaN as 0) to 8-bit RGB. */
static void magma(float v, uint8_t *out)
{
    static const float stops[9][3] = {{0, 0, 4},      {28, 16, 68},   {79, 18, 123},   {129, 37, 129}, {181, 54, 122},
                                      {229, 80, 100}, {251, 135, 97}, {254, 194, 135}, {252, 253, 191}};
    v = v < 0 || !isfinite(v) ? 0 : (v > 1 ? 1 : v);
    float x = v * 8.f;
    int k = (int)x;
    if (k >= 8)
        k = 7;
    float f = x - k;
    for (int c = 0; c < 3; c++)
        out[c] = (uint8_t)lrintf(stops[k][c] * (1 - f) + stops[k + 1][c] * f);
}

/* A 5×7 pixel font for the colour bar's labels: each glyph is 7 rows of 5
 * bits, the high bit leftmost. */
static const struct {
    char c;
    uint8_t rows[7];
} k_glyphs[] = {
    {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},     {'2', {14, 17, 1, 2, 4, 8, 31}},
    {'3', {30, 1, 1, 14, 1, 1, 30}},     {'4', {2, 6, 10, 18, 31, 2, 2}},    {'5', {31, 16, 30, 1, 1, 17, 14}},
    {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},      {'8', {14, 17, 17, 14, 17, 17, 14}},
    {'9', {14, 17, 17, 15, 1, 2, 12}},   {'.', {0, 0, 0, 0, 0, 12, 12}},     {'-', {0, 0, 0, 31, 0, 0, 0}},
    {'+', {0, 4, 4, 31, 4, 4, 0}},       {'e', {0, 0, 14, 17, 31, 16, 14}},  {'r', {0, 0, 22, 25, 16, 16, 16}},
    {'m', {0, 0, 26, 21, 21, 21, 21}},   {'s', {0, 0, 15, 16, 14, 1, 30}},   {'l', {12, 4, 4, 4, 4, 4, 14}},
    {'f', {6, 9, 8, 28, 8, 8, 8}},       {'i', {4, 0, 12, 4, 4, 4, 14}},     {'p', {0, 0, 30, 17, 30, 16, 16}},
    {'S', {15, 16, 16, 14, 1, 1, 30}},   {'I', {14, 4, 4, 4, 4, 4, 14}},     {'M', {17, 27, 21, 21, 17, 17, 17}},
    {'F', {31, 16, 16, 30, 16, 16, 16}}, {'L', {16, 16, 16, 16, 16, 16, 31}}, {'P', {30, 17, 17, 30, 16, 16, 16}},
    {'R', {30, 17, 17, 30, 20, 18, 17}}, {'E', {31, 16, 16, 30, 16, 16, 31}},
};

/* Draws `text` into the w-wide RGB image px with its top-left corner at
 * (x, y), each font pixel s×s; characters without a glyph are spaces.
 * Returns the text's width. */
static int draw_text(uint8_t *px, int w, int h, int x, int y, int s, const char *text, const uint8_t rgb[3])
{
    int x0 = x;
    for (const char *t = text; *t; t++, x += 6 * s) {
        const uint8_t *rows = NULL;
        for (size_t g = 0; g < sizeof k_glyphs / sizeof k_glyphs[0] && !rows; g++)
            if (k_glyphs[g].c == *t)
                rows = k_glyphs[g].rows;
        for (int r = 0; rows && r < 7 * s; r++)
            for (int c = 0; c < 5 * s; c++) {
                int u = x + c, v = y + r;
                if (u >= 0 && v >= 0 && u < w && v < h && (rows[r / s] >> (4 - c / s) & 1))
                    memcpy(px + 3 * ((size_t)v * w + u), rgb, 3);
            }
    }
    return x - x0;
}

int metric_write_heatmap_bar(const char *path, const float *map, int w, int h, const char *name, double full)
{
    /* Below the map: a band of the scale from 0 to 1, then "0", the
     * metric's name and the value of full heat, in a 5×7 font (2× from 240
     * pixels wide). Too narrow for the text (under 60 pixels): the band alone. */
    int s = w >= 240 ? 2 : 1, band = 6 * s, text_h = w >= 60 ? 11 * s : 0, bar = band + text_h + 2 * s;
    size_t n = (size_t)w * ((size_t)h + (size_t)bar);
    uint8_t *px = util_malloc("compare", "the heat map image", n, 3);
    if (!px)
        return 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        magma(map[i], px + 3 * i);
    memset(px + 3 * (size_t)w * h, 24, 3 * (size_t)w * bar); /* dark grey under the map */
    for (int y = h + s; y < h + s + band; y++)
        for (int x = 0; x < w; x++)
            magma(w > 1 ? (float)x / (float)(w - 1) : 1.f, px + 3 * ((size_t)y * w + x));
    if (text_h) {
        static const uint8_t white[3] = {235, 235, 235};
        char hi[32];
        snprintf(hi, sizeof hi, "%.3g", full);
        int y = h + 2 * s + band, wide = (int)strlen(hi) * 6 * s;
        draw_text(px, w, h + bar, s, y, s, "0", white);
        draw_text(px, w, h + bar, w - wide, y, s, hi, white);
        int name_w = (int)strlen(name) * 6 * s;
        if (name_w + wide + 12 * s < w) /* the name, where it fits between them */
            draw_text(px, w, h + bar, (w - name_w) / 2, y, s, name, white);
    }
    int ok = image_write_png8(path, w, h + bar, px);
    free(px);
    return ok;
}

int metric_write_heatmap(const char *path, const float *map, int w, int h)
{
    uint8_t *px = util_malloc("compare", "the heat map image", (size_t)w * h, 3);
    if (!px)
        return 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        magma(map[i], px + 3 * i);
    int ok = image_write_png8(path, w, h, px);
    free(px);
    return ok;
}

double metric_mean_ratio(const ImageF *test, const ImageF *ref, const uint8_t *mask, double rgb[3])
{
    double st[4] = {0}, sr[4] = {0};
    size_t np = (size_t)test->width * test->height;
    for (size_t i = 0; i < np; i++) {
        if (mask && !mask[i])
            continue;
        const float *t = test->rgb + 3 * i, *r = ref->rgb + 3 * i;
        for (int c = 0; c < 3; c++) {
            st[c] += t[c];
            sr[c] += r[c];
        }
        st[3] += luminance(t);
        sr[3] += luminance(r);
    }
    for (int c = 0; rgb && c < 3; c++)
        rgb[c] = sr[c] > 0 ? st[c] / sr[c] : NAN;
    return sr[3] > 0 ? st[3] / sr[3] : NAN;
}

ShadowArtefacts metric_shadow_artefacts(const ImageF *test, const ImageF *ref, const ImageF *unshadowed,
                                        const uint8_t *mask)
{
    size_t np = (size_t)test->width * test->height, counted = 0, dark = 0, bright = 0;
    double mean = 0;
    for (size_t i = 0; i < np; i++)
        if (!mask || mask[i]) {
            mean += luminance(unshadowed->rgb + 3 * i);
            counted++;
        }
    double floor = counted ? 1e-4 * mean / (double)counted : 0;
    ShadowArtefacts a = {0};
    for (size_t i = 0; i < np; i++) {
        double u = luminance(unshadowed->rgb + 3 * i);
        if ((mask && !mask[i]) || !(u > floor))
            continue;
        double vr = luminance(ref->rgb + 3 * i) / u, vt = luminance(test->rgb + 3 * i) / u;
        if (vr >= 0.95) {
            a.lit++;
            dark += vt < 0.5;
        } else if (vr <= 0.05) {
            a.shadowed++;
            bright += vt > 0.5;
        }
    }
    a.false_shadow = a.lit ? (double)dark / (double)a.lit : NAN;
    a.false_lit = a.shadowed ? (double)bright / (double)a.shadowed : NAN;
    return a;
}

bool metric_block_average(const ImageF *img, const uint8_t *mask, int block, ImageF *out, uint8_t **out_mask)
{
    int bw = (img->width + block - 1) / block, bh = (img->height + block - 1) / block;
    uint8_t *m = util_malloc("metrics", "a block mask", (size_t)bw * bh, 1);
    if (!m || !image_alloc(out, bw, bh)) { /* each logs its line */
        free(m);
        return false;
    }
    for (int by = 0; by < bh; by++)
        for (int bx = 0; bx < bw; bx++) {
            double sum[3] = {0, 0, 0};
            int n = 0;
            for (int y = by * block; y < (by + 1) * block && y < img->height; y++)
                for (int x = bx * block; x < (bx + 1) * block && x < img->width; x++) {
                    if (mask && !mask[(size_t)y * img->width + x])
                        continue;
                    const float *p = image_px(img, x, y);
                    for (int c = 0; c < 3; c++)
                        sum[c] += p[c];
                    n++;
                }
            float *q = image_px(out, bx, by);
            for (int c = 0; c < 3; c++)
                q[c] = n ? (float)(sum[c] / n) : 0.f;
            m[(size_t)by * bw + bx] = n > 0;
        }
    *out_mask = m;
    return true;
}
