/*
 * qibl.h - umbrella header: everything the core offers, for callers who do not pick modules.
 */
#ifndef QIBL_H
#define QIBL_H

#include "qibl/config.h"
#include "qibl/version.h"
#include "qibl/status.h"
#include "qibl/fixed.h"
#include "qibl/sh.h"
#include "qibl/srgbe.h"
#include "qibl/shmaps.h"
#include "qibl/asset.h"
#include "qibl/shmap.h"
#include "qibl/lightpath.h"
#include "qibl/lightprobe.h"
#include "qibl/probe.h"
#include "qibl/hemi.h"
#include "qibl/gonio.h"
#include "qibl/isa.h"

#endif /* QIBL_H */
