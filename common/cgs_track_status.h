/* cgs_track_status — a track's status as the `track` topic carries it
 * (cgs.TrackStatus in proto/tracking.proto), for the cores that must not
 * see protobuf-c: the tracker that sets it and the guidance that reads it.
 * cgs_msg.c checks at compile time that the values are the message's. */
#ifndef CGS_TRACK_STATUS_H
#define CGS_TRACK_STATUS_H

typedef enum {
    CGS_TRACK_TENTATIVE = 0, // not yet confirmed
    CGS_TRACK_CONFIRMED = 1, // hit in its latest scan
    CGS_TRACK_COASTING = 2,  // confirmed, missed its latest scan(s)
    CGS_TRACK_DELETED = 3,   // reported once, then forgotten
} cgs_track_status_t;

#define CGS_TRACK_STATUS_MAX CGS_TRACK_DELETED

#endif
