/* tb_trv_stack.c — the TRV's banked traversal stack (model/ray/trv_stack.h):
 * bank conflicts and overflow. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/ray/trv_stack.h"
#include "testbench/tb.h"

/* -------------------------------------------------------------- trv stack */

static void test_stack_banks(void)
{
    tb_begin("trv_stack_banking_and_conflicts");
    char err[200];
    trv_stack s;
    TB_CHECK(trv_stack_init(&s, 4, 8, 3, err, sizeof err), "%s", err);
    trv_stack_entry e[4] = {{1, 0, 1.0f}, {2, 0, 2.0f}, {3, 4, 3.0f}, {4, 0, 4.0f}};
    /* 3 pushes over 3 banks: one cycle (MBVH4 with N-1 banks) */
    TB_EQ_INT(trv_stack_push(&s, 1, e, 3), 1);
    TB_EQ_INT(s.st.conflict_cycles, 0);
    TB_EQ_INT(trv_stack_size(&s, 1), 3);
    TB_EQ_INT(trv_stack_size(&s, 0), 0);
    trv_stack_entry top;
    TB_CHECK(trv_stack_peek(&s, 1, 0, &top) && top.ref == 3 && top.meta == 4 && top.tnear == 3.0f, "top is last pushed");
    TB_CHECK(trv_stack_peek(&s, 1, 2, &top) && top.ref == 1, "bottom is first pushed");
    TB_CHECK(!trv_stack_peek(&s, 1, 3, &top), "no 4th entry");
    /* 4 entries over 3 banks: two land in one bank -> 2 cycles, 1 conflict */
    TB_EQ_INT(trv_stack_push(&s, 2, e, 4), 2);
    TB_EQ_INT(s.st.conflict_cycles, 1);
    /* pops: 1 entry 1 cycle; 3 at once (culls) 1 cycle */
    TB_EQ_INT(trv_stack_pop(&s, 2, 1), 1);
    TB_EQ_INT(trv_stack_pop(&s, 2, 3), 1);
    TB_CHECK(trv_stack_empty(&s, 2), "emptied");
    /* overflow: 3 + 4 + 2 > 8 entries: reported, nothing pushed */
    TB_EQ_INT(trv_stack_push(&s, 1, e, 4), 2);
    TB_EQ_INT(trv_stack_push(&s, 1, e, 2), -1);
    TB_EQ_INT(trv_stack_size(&s, 1), 7);
    TB_EQ_INT(s.st.overflows, 1);
    TB_EQ_INT(s.st.max_depth, 7);
    trv_stack_free(&s);
    /* a single bank (BVH2 baseline) serialises multi-entry operations */
    TB_CHECK(trv_stack_init(&s, 1, 64, 1, err, sizeof err), "%s", err);
    TB_EQ_INT(trv_stack_push(&s, 0, e, 3), 3);
    TB_EQ_INT(trv_stack_pop(&s, 0, 2), 2);
    TB_EQ_INT(s.st.conflict_cycles, 3);
    trv_stack_free(&s);
    TB_CHECK(!trv_stack_init(&s, 0, 64, 1, err, sizeof err) && strstr(err, "slots 0"), "zero slots refused: %s", err);
    TB_CHECK(!trv_stack_init(&s, 4, 64, 0, err, sizeof err) && strstr(err, "banks 0"), "zero banks refused: %s", err);
    tb_end();
}

int main(void)
{
    test_stack_banks();
    return tb_finish();
}
