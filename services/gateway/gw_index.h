/* gw_index — a hash index from 64-bit keys (entity ids, DIS ids) to array
 * positions: open addressing with linear probing, grown at half full. Pure. */
#ifndef GW_INDEX_H
#define GW_INDEX_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct gw_index gw_index_t;

/* An empty index, or NULL without memory. */
gw_index_t *gw_index_new (void);
/* Free; accepts NULL; nulls the pointer. */
void gw_index_destroy (gw_index_t **self_p);
/* Map key to value (replacing what it mapped to); 0 or -ENOMEM. */
int gw_index_put (gw_index_t *self, uint64_t key, size_t value);
/* The value of key into *ret_value; false when the key is absent. */
bool gw_index_get (const gw_index_t *self, uint64_t key, size_t *ret_value);
/* Forget every key. */
void gw_index_clear (gw_index_t *self);

#endif
