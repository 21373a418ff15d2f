/* mesh.c — see mesh.h. */
#include "tracer/mesh.h"

#include <stdlib.h>
#include <string.h>

void rt_mesh_free(rt_mesh *m)
{
    free(m->verts);
    free(m->tris);
    memset(m, 0, sizeof *m);
}
