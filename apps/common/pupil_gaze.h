// Gaze from a Pupil Labs Core tracker over its network API (Pupil Capture or Pupil Service
// with the Pupil Remote plugin): ZeroMQ sockets, msgpack payloads. docs/fovview.md, "Gaze
// sources", documents the exchange, the coordinate mapping and the clock.
//
//  1. A REQ socket to Pupil Remote (tcp://HOST:PORT, Pupil's default port 50020) asks
//     "SUB_PORT" (the answer: the port of its IPC backbone's publisher) and "t" (its clock,
//     seconds, as text);
//  2. a SUB socket on HOST:SUB_PORT subscribes to the topic prefix ("gaze." by default, or
//     "surfaces.NAME" for gaze mapped onto a tracked surface such as the screen) and
//     receives two-frame messages: the topic ("gaze.3d.0." right eye, "gaze.3d.1." left eye,
//     "gaze.3d.01." both; "gaze.2d.*" alike) and a msgpack map with norm_pos [x, y]
//     (0..1, origin bottom-left), confidence (0..1) and timestamp (Pupil's clock, s);
//  3. norm_pos is turned to the top-left convention (y -> 1 - y), through the calibration,
//     and scaled to the screen; the timestamp is mapped to gaze_clock_ms() by a tracker_clock
//     synchronised with "t" once a second and again after a jump.
// A background thread receives (so arrival times do not wait for the frame loop); read()
// hands over what it queued. After the start nothing the tracker does ends the session:
// malformed messages are counted, a silent publisher leaves the conditioner to its dropout
// policy, a Remote that stops answering is asked again.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gaze_source.h"

namespace fov {

struct pupil_params {
  std::string endpoint;          // Pupil Remote, tcp://HOST:PORT
  std::string topic = "gaze.";   // the subscription prefix
  double timeout_ms = 1000;      // how long to wait for Pupil Remote's answers at the start
  double sync_every_ms = 1000;   // how often to ask for its clock
};

// Splits "tcp://HOST:PORT"; "" or the reason it is not one.
std::string parse_pupil_endpoint(const std::string& text, std::string& host, uint16_t& port);

// One gaze message, decoded. norm_x, norm_y as Pupil sends them (origin bottom-left).
struct pupil_gaze_message {
  double norm_x = 0, norm_y = 0, confidence = 0, timestamp = 0;
  gaze_eye eye = gaze_eye::both;
};
// Decodes the topic frame and the msgpack payload into its gaze data: one for a "gaze."
// topic; for a surface topic ("surfaces.NAME", Pupil's surface tracker) every entry of
// gaze_on_surfaces, in the surface's coordinates (origin bottom-left, the surface's corners
// 0 and 1; none when the list is empty). "" or why the message is malformed. Never
// allocates more than a small multiple of `size`.
std::string parse_pupil_gaze(const std::string& topic, const unsigned char* payload, size_t size,
                             std::vector<pupil_gaze_message>& out);

// Connects, asks SUB_PORT and t, subscribes and starts receiving. Throws std::runtime_error
// "--gaze-pupil ENDPOINT: reason" when Pupil Remote does not answer in time or answers
// something that is not Pupil Remote's.
std::unique_ptr<gaze_source> pupil_gaze(const pupil_params& params, const gaze_calibration& calibration, int width,
                                        int height);

}  // namespace fov
