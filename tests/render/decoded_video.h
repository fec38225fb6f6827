// A video file read back the way a player reads it (libavformat, libavcodec, libswscale), for the
// tests of render/video_writer.cpp and `dwatch render --video`: written apart from the writer, so
// that a wrong container, codec, size, frame count or colour conversion there shows here.
#pragma once

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "render/image.h"

namespace dw::render::test {

struct DecodedVideo {
  std::string error;      // empty when the file decoded
  std::string container;  // libavformat's name for it: "mov,mp4,m4a,3gp,3g2,mj2", "matroska,webm"
  std::string codec;      // "h264", "vp9"
  std::string pixel_format;
  int width = 0, height = 0;
  double fps = 0;                     // the stream's average frame rate
  std::vector<render::Image> frames;  // RGBA, in presentation order
};

inline DecodedVideo decode_video(const std::string& path) {
  DecodedVideo v;
  auto av_text = [](int code) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof text);
    return std::string(text);
  };
  AVFormatContext* raw_input = nullptr;
  if (int r = avformat_open_input(&raw_input, path.c_str(), nullptr, nullptr); r < 0) {
    v.error = "cannot open " + path + ": " + av_text(r);
    return v;
  }
  std::unique_ptr<AVFormatContext*, void (*)(AVFormatContext**)> input(&raw_input, avformat_close_input);
  if (int r = avformat_find_stream_info(raw_input, nullptr); r < 0) {
    v.error = "no stream information: " + av_text(r);
    return v;
  }
  v.container = raw_input->iformat->name;
  const AVCodec* decoder = nullptr;
  const int index = av_find_best_stream(raw_input, AVMEDIA_TYPE_VIDEO, -1, -1, &decoder, 0);
  if (index < 0 || !decoder) {
    v.error = "no video stream";
    return v;
  }
  const AVStream* stream = raw_input->streams[index];
  v.codec = avcodec_get_name(stream->codecpar->codec_id);
  v.fps = av_q2d(stream->avg_frame_rate);
  AVCodecContext* raw_codec = avcodec_alloc_context3(decoder);
  std::unique_ptr<AVCodecContext*, void (*)(AVCodecContext**)> codec(&raw_codec, avcodec_free_context);
  avcodec_parameters_to_context(raw_codec, stream->codecpar);
  if (int r = avcodec_open2(raw_codec, decoder, nullptr); r < 0) {
    v.error = "cannot open the decoder: " + av_text(r);
    return v;
  }
  v.width = raw_codec->width;
  v.height = raw_codec->height;
  v.pixel_format = av_get_pix_fmt_name(raw_codec->pix_fmt) ? av_get_pix_fmt_name(raw_codec->pix_fmt) : "";

  AVFrame* raw_frame = av_frame_alloc();
  std::unique_ptr<AVFrame*, void (*)(AVFrame**)> frame(&raw_frame, av_frame_free);
  AVPacket* raw_packet = av_packet_alloc();
  std::unique_ptr<AVPacket*, void (*)(AVPacket**)> packet(&raw_packet, av_packet_free);
  // Each decoded picture to RGBA by the matrix and range the file declares, as a player does.
  auto take_frames = [&]() -> bool {
    for (;;) {
      const int r = avcodec_receive_frame(raw_codec, raw_frame);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return true;
      if (r < 0) {
        v.error = "decoding failed: " + av_text(r);
        return false;
      }
      SwsContext* to_rgba =
          sws_getContext(raw_frame->width, raw_frame->height, AVPixelFormat(raw_frame->format), raw_frame->width,
                         raw_frame->height, AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
      const int matrix = raw_frame->colorspace == AVCOL_SPC_BT709 ? SWS_CS_ITU709 : SWS_CS_DEFAULT;
      const int* coefficients = sws_getCoefficients(matrix);
      sws_setColorspaceDetails(to_rgba, coefficients, raw_frame->color_range == AVCOL_RANGE_JPEG, coefficients, 1, 0,
                               1 << 16, 1 << 16);
      render::Image image(raw_frame->width, raw_frame->height);
      uint8_t* rows[1] = {image.rgba.data()};
      const int stride[1] = {image.width * 4};
      sws_scale(to_rgba, raw_frame->data, raw_frame->linesize, 0, raw_frame->height, rows, stride);
      sws_freeContext(to_rgba);
      v.frames.push_back(std::move(image));
      av_frame_unref(raw_frame);
    }
  };
  while (av_read_frame(raw_input, raw_packet) >= 0) {
    const bool ours = raw_packet->stream_index == index;
    if (ours && avcodec_send_packet(raw_codec, raw_packet) < 0) {
      v.error = "a packet the decoder refuses";
      return v;
    }
    av_packet_unref(raw_packet);
    if (ours && !take_frames()) return v;
  }
  avcodec_send_packet(raw_codec, nullptr);  // the frames the decoder still holds
  take_frames();
  return v;
}

// The mean of |a - b| over the red, green and blue channels of every pixel (0..255); a large
// number when the sizes differ.
inline double mean_absolute_difference(const render::Image& a, const render::Image& b) {
  if (a.width != b.width || a.height != b.height) return 1e9;
  uint64_t sum = 0;
  for (size_t i = 0; i < a.rgba.size(); i += 4)
    for (size_t c = 0; c < 3; ++c) sum += uint64_t(std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])));
  return double(sum) / double(a.rgba.size() / 4 * 3);
}

// The pixels of a highlighted group's outline and slot links (renderer.cpp's kOutline, 214,28,41)
// after lossy compression: strongly red.
inline bool group_red(const uint8_t* p) { return p[0] > 150 && p[1] < 90 && p[2] < 100; }

inline int64_t count_pixels(const render::Image& image, bool (*test)(const uint8_t*)) {
  int64_t n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += test(image.pixel(x, y)) ? 1 : 0;
  return n;
}

}  // namespace dw::render::test
