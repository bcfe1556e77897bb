/* ms_cmd_sensor — the imaging sensor's commands: `mscgs camera` (uavsim
 * points the camera: depression, field of view, stabilization, stare) and
 * `mscgs sensor` (imagerd's mode: visible, infrared or SAR). Each takes the
 * command line from its name on and returns the exit code. */
#ifndef MS_CMD_SENSOR_H
#define MS_CMD_SENSOR_H

/* mscgs camera [--depression DEG] [--fov DEG] [--stabilized on|off]
 * [--stare off|target|POS] [--uav ID] [--to INSTANCE] [--exercise F]. */
int ms_camera_main (int argc, char **argv);

/* mscgs sensor visible|infrared|flir|sar [--uav ID] [--to INSTANCE]. */
int ms_sensor_main (int argc, char **argv);

#endif
