/*
 * ref/psnr.h - the one PSNR of the tools: 8-bit data (peak 255), in dB, from a mean squared error.
 * Every table, RESULT line and budget of the CLI (demo, bake --budget, bench relight) goes through
 * it, so their figures are comparable and capped alike. Hosted (libm).
 */
#ifndef QTOOL_REF_PSNR_H
#define QTOOL_REF_PSNR_H

/* 10 log10(255^2 / mse); 99 for mse <= 0 (identical data), the cap every figure uses. */
double qtool_ref_psnr8(double mse);

#endif
