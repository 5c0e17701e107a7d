/*
 * ref/psnr.c - PSNR of 8-bit data from a mean squared error (see psnr.h).
 */
#include "ref/psnr.h"

#include <math.h>

double qtool_ref_psnr8(double mse)
{
    return mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : 99.0;
}
