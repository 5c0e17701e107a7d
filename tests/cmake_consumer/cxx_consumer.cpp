// cxx_consumer.cpp - an engine's C++ code using qibl through the CMake target: the start-up check,
// then one directional light's weights for a 1x1 SH map built by hand (no asset needed).
#include <cstdio>

#include "qibl.h"
#include "qibl/soft.h"

int main()
{
    if (qibl_init_check() != QIBL_OK) {
        std::fprintf(stderr, "cxx_consumer: %s\n", qibl_status_str(qibl_init_check()));
        return 1;
    }
    qibl_shlight_t light;
    const qibl_q16_t sun[3] = {0, 0, QIBL_Q16_ONE}, rgb[3] = {QIBL_Q16_ONE, QIBL_Q16_ONE, QIBL_Q16_ONE};
    qibl_status_t st = qibl_shlight_init(&light, 9);
    if (st == QIBL_OK)
        st = qibl_shlight_add_dir(&light, sun, rgb);
    std::printf("cxx_consumer: qibl %s, config id %08lx, light: %s\n", qibl_version(),
                static_cast<unsigned long>(qibl_config_id()), qibl_status_str(st));
    return st == QIBL_OK ? 0 : 1;
}
