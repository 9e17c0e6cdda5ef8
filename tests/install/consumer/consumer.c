/* SPDX-License-Identifier: BSD-3-Clause */
/* consumer.c - an installed kinctl's user: FK of the built-in puma560 and
 * of the same arm read from a description file, printed as one JSON line.
 *
 *   consumer MODEL_FILE q1 q2 q3 q4 q5 q6
 *   {"real":"double","builtin":[t0..t11],"file":[...]}   (rows of R, then t)
 */
#include <stdio.h>
#include <stdlib.h>

#include "kinctl/desc.h"
#include "kinctl/kinctl.h"

static void print_pose(const char *name, const kc_pose *p)
{
    int i, j;
    printf("\"%s\":[", name);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            printf("%.17g,", (double)p->R.m[i][j]);
    printf("%.17g,%.17g,%.17g]", (double)p->t.v[0], (double)p->t.v[1], (double)p->t.v[2]);
}

int main(int argc, char **argv)
{
    kc_chain builtin, file;
    kc_desc_info info;
    kc_desc_error err;
    kc_real q[6];
    kc_pose a, b;
    kc_status st;
    int i;

    if (argc != 8) {
        fprintf(stderr, "usage: consumer MODEL_FILE q1 .. q6\n");
        return 2;
    }
    for (i = 0; i < 6; i++)
        q[i] = (kc_real)strtod(argv[2 + i], NULL);
    st = kc_chain_init_model(&builtin, KC_MODEL_PUMA560, NULL);
    if (st == KC_OK)
        st = kc_fk_eval(&builtin, q, &a);
    if (st != KC_OK) {
        fprintf(stderr, "consumer: built-in puma560: %s\n", kc_status_str(st));
        return 1;
    }
    st = kc_desc_load_file(argv[1], &file, &info, &err);
    if (st == KC_OK)
        st = kc_fk_eval(&file, q, &b);
    if (st != KC_OK) {
        fprintf(stderr, "consumer: %s: %s\n", argv[1], kc_status_str(st));
        return 1;
    }
    printf("{\"real\":\"%s\",", KC_REAL_NAME);
    print_pose("builtin", &a);
    printf(",");
    print_pose("file", &b);
    printf("}\n");
    return 0;
}
