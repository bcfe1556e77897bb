/* gw_index — open-addressing hash index. */
#include "gw_index.h"

#include <errno.h>
#include <stdlib.h>

typedef struct {
    uint64_t key;
    size_t value_1; // value + 1; 0 marks an empty slot
} s_slot_t;

struct gw_index {
    s_slot_t *slots;
    size_t cap, used; // cap: a power of two
};

static size_t s_hash (uint64_t k)
{
    // splitmix64's finaliser spreads neighbouring ids over the table.
    k ^= k >> 30;
    k *= 0xbf58476d1ce4e5b9ULL;
    k ^= k >> 27;
    k *= 0x94d049bb133111ebULL;
    k ^= k >> 31;
    return (size_t)k;
}

gw_index_t *gw_index_new (void)
{
    gw_index_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->cap = 64;
    self->slots = calloc (self->cap, sizeof *self->slots);
    if (!self->slots)
        gw_index_destroy (&self);
    return self;
}

void gw_index_destroy (gw_index_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    free ((*self_p)->slots);
    free (*self_p);
    *self_p = NULL;
}

static s_slot_t *s_find (s_slot_t *slots, size_t cap, uint64_t key)
{
    size_t i = s_hash (key) & (cap - 1);
    while (slots[i].value_1 && slots[i].key != key)
        i = (i + 1) & (cap - 1);
    return &slots[i];
}

int gw_index_put (gw_index_t *self, uint64_t key, size_t value)
{
    if ((self->used + 1) * 2 > self->cap) {
        size_t cap = self->cap * 2;
        s_slot_t *slots = calloc (cap, sizeof *slots);
        if (!slots)
            return -ENOMEM;
        for (size_t i = 0; i < self->cap; i++)
            if (self->slots[i].value_1)
                *s_find (slots, cap, self->slots[i].key) = self->slots[i];
        free (self->slots);
        self->slots = slots;
        self->cap = cap;
    }
    s_slot_t *s = s_find (self->slots, self->cap, key);
    if (!s->value_1)
        self->used++;
    s->key = key;
    s->value_1 = value + 1;
    return 0;
}

bool gw_index_get (const gw_index_t *self, uint64_t key, size_t *ret_value)
{
    const s_slot_t *s = s_find (self->slots, self->cap, key);
    if (!s->value_1)
        return false;
    *ret_value = s->value_1 - 1;
    return true;
}

void gw_index_clear (gw_index_t *self)
{
    for (size_t i = 0; i < self->cap; i++)
        self->slots[i].value_1 = 0;
    self->used = 0;
}
