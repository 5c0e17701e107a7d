/*
 * gen-sh-rot-table.c - prints the const tables of qibl_sh_rotation_init (core/src/sh.c): N sample
 * directions (spherical Fibonacci, Q2.30) and, per band l = 1..4, the least-squares inverse
 * pinv_l = (Y_l^T Y_l)^-1 Y_l^T of the band's basis at those directions (Q2.30), computed in double
 * from the Q2.30-rounded directions with tools/ref/sh_ref.c. Hosted; run by hand:
 *   cc -std=c99 -O2 -Itools tools/scripts/gen-sh-rot-table.c tools/ref/sh_ref.c -lm && ./a.out
 * tests/sh_test.c recomputes the tables the same way and checks them within 1 LSB.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "ref/sh_ref.h"

#define N 16

static void inv(int n, double *a) /* Gauss-Jordan, a n x n, in place (symmetric positive definite) */
{
    double *b = calloc((size_t)(n * 2 * n), sizeof *b);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j)
            b[i * 2 * n + j] = a[i * n + j];
        b[i * 2 * n + n + i] = 1;
    }
    for (int c = 0; c < n; ++c) {
        int p = c;
        for (int r = c + 1; r < n; ++r)
            if (fabs(b[r * 2 * n + c]) > fabs(b[p * 2 * n + c]))
                p = r;
        for (int j = 0; j < 2 * n; ++j) {
            double t = b[c * 2 * n + j];
            b[c * 2 * n + j] = b[p * 2 * n + j];
            b[p * 2 * n + j] = t;
        }
        double d = b[c * 2 * n + c];
        for (int j = 0; j < 2 * n; ++j)
            b[c * 2 * n + j] /= d;
        for (int r = 0; r < n; ++r)
            if (r != c) {
                double f = b[r * 2 * n + c];
                for (int j = 0; j < 2 * n; ++j)
                    b[r * 2 * n + j] -= f * b[c * 2 * n + j];
            }
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            a[i * n + j] = b[i * 2 * n + n + j];
    free(b);
}

int main(int argc, char **argv)
{
    int verbose = argc > 1;
    long dq[N][3];
    double Y[N][25];
    const double ga = 3.14159265358979323846 * (3.0 - sqrt(5.0));
    for (int k = 0; k < N; ++k) {
        double z = 1.0 - (2.0 * k + 1.0) / N, r = sqrt(1.0 - z * z), p = ga * k;
        double d[3] = {r * cos(p), r * sin(p), z};
        for (int c = 0; c < 3; ++c)
            dq[k][c] = lrint(d[c] * 1073741824.0);
        qtool_ref_sh_eval((double)dq[k][0], (double)dq[k][1], (double)dq[k][2], 5, Y[k]);
    }
    printf("/* sample directions, Q2.30 (spherical Fibonacci, %d points) */\n", N);
    printf("static const int32_t rot_dirs[%d][3] = {\n", N);
    for (int k = 0; k < N; ++k)
        printf("    {%11ld, %11ld, %11ld},\n", dq[k][0], dq[k][1], dq[k][2]);
    printf("};\n\n/* pinv_l[m][k], bands 1..4 one after the other (3 + 5 + 7 + 9 rows), Q2.30 */\n");
    printf("static const int32_t rot_pinv[24][%d] = {\n", N);
    for (int l = 1; l <= 4; ++l) {
        int n = 2 * l + 1;
        double A[81], P[9][N];
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double s = 0;
                for (int k = 0; k < N; ++k)
                    s += Y[k][l * l + i] * Y[k][l * l + j];
                A[i * n + j] = s;
            }
        double At[81];
        for (int i = 0; i < n * n; ++i)
            At[i] = A[i];
        inv(n, A);
        double rowmax = 0;
        for (int i = 0; i < n; ++i) {
            double rs = 0;
            for (int k = 0; k < N; ++k) {
                double s = 0;
                for (int j = 0; j < n; ++j)
                    s += A[i * n + j] * Y[k][l * l + j];
                P[i][k] = s;
                rs += fabs(s);
            }
            if (rs > rowmax)
                rowmax = rs;
        }
        if (verbose) {
            double nrm = 0, nrmi = 0; /* inf norms as a condition estimate */
            for (int i = 0; i < n; ++i) {
                double a = 0, b = 0;
                for (int j = 0; j < n; ++j)
                    a += fabs(At[i * n + j]), b += fabs(A[i * n + j]);
                nrm = fmax(nrm, a), nrmi = fmax(nrmi, b);
            }
            fprintf(stderr, "band %d: cond_inf(Y^T Y) %.2f, max row sum |pinv| %.3f\n", l, nrm * nrmi, rowmax);
        }
        for (int i = 0; i < n; ++i) {
            printf("    {");
            for (int k = 0; k < N; ++k)
                printf("%s%ld", k ? ", " : "", lrint(P[i][k] * 1073741824.0));
            printf("}, /* l=%d m=%d */\n", l, i - l);
        }
    }
    printf("};\n");
    return 0;
}
