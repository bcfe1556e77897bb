/* libFuzzer target: any bytes as the payload of every catalogue topic and as
 * a command, decoded and printed as JSON the way subscribers and `mscgs echo`
 * do. Must never crash, leak or hit undefined behaviour. */
#include "cgs_msg.h"
#include "cgs_topics.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size)
{
    static cgs_msg_arena_t *arena;
    if (!arena)
        arena = cgs_msg_arena_new (4096);
    for (size_t i = 0; i <= cgs_topics_count (); i++) {
        const ProtobufCMessageDescriptor *d =
            i < cgs_topics_count () ? cgs_topics_at (i)->message : &cgs__command__descriptor;
        ProtobufCMessage *m = NULL;
        if (cgs_msg_decode (d, data, size, arena, &m) == 0) {
            char *json = NULL;
            if (cgs_msg_to_json (m, &json) == 0)
                free (json);
            (void)cgs_msg_header (m);
        }
        cgs_msg_arena_reset (arena);
        if (cgs_msg_decode (d, data, size, NULL, &m) == 0)
            cgs_msg_free (&m);
    }
    return 0;
}
