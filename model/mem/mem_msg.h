/* mem_msg.h — the messages that travel on the memory-side FIFO channels
 * (cache <-> cache, cache <-> arbiter, arbiter <-> DRAM port / fixed-latency
 * memory). One request is one line fill (or one write-back); `src` routes the
 * response back through arbiters, `tag` is the requester's own (e.g. the MSHR
 * index). Plain data: copied by value into kernel FIFOs. */
#ifndef RTSIM_MODEL_MEM_MSG_H
#define RTSIM_MODEL_MEM_MSG_H

#include <stdint.h>

typedef struct mem_req {
    uint64_t addr;      /* byte address in the memory image, line aligned */
    uint32_t bytes;     /* line size of the requester */
    uint16_t src;       /* requester port index at the next arbiter */
    uint8_t is_write;
    uint8_t pad;
    uint64_t tag;       /* returned unchanged in the response */
} mem_req;

typedef struct mem_resp {
    uint64_t addr;
    uint32_t bytes;
    uint16_t src;
    uint16_t pad;
    uint64_t tag;
} mem_resp;

#endif
