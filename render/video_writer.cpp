#include "render/video_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include "sim/output_file.h"

namespace dw::render {
namespace {

// A codec and its container, chosen by the file name's extension.
struct Format {
  const char* extension;
  const char* muxer;    // libavformat's name
  const char* encoder;  // libavcodec's name
  const char* codec;    // as a person says it
  const char* package;  // where Debian's libavcodec gets the encoder from
};
constexpr Format kFormats[] = {
    {".mp4", "mp4", "libx264", "H.264", "libx264"},
    {".webm", "webm", "libvpx-vp9", "VP9", "libvpx"},
};

// The libav* functions the writer calls, opened by soname when a video is first written rather
// than linked: libavcodec and libavformat bring codecs and protocols (x265, dav1d, librsvg, GnuTLS
// ...), some 22 MiB of every process that loads them, which only a video needs. RTLD_NODELETE
// keeps them loaded once opened (libav's codecs are not made to be unloaded).
// Each function the writer calls, by the library it is in (LibAv::handles_).
// clang-format off
#define DW_LIBAV_FUNCTIONS(X)                                                                                 \
  X(0, av_dict_free) X(0, av_dict_set) X(0, av_frame_alloc) X(0, av_frame_free) X(0, av_frame_get_buffer)     \
  X(0, av_frame_make_writable) X(0, av_free) X(0, av_freep) X(0, av_malloc) X(0, av_strerror)                 \
  X(1, av_packet_alloc) X(1, av_packet_free) X(1, av_packet_rescale_ts) X(1, avcodec_alloc_context3)          \
  X(1, avcodec_find_encoder_by_name) X(1, avcodec_free_context) X(1, avcodec_open2)                           \
  X(1, avcodec_parameters_from_context) X(1, avcodec_receive_packet) X(1, avcodec_send_frame)                 \
  X(2, av_interleaved_write_frame) X(2, av_write_trailer) X(2, avformat_alloc_output_context2)                \
  X(2, avformat_free_context) X(2, avformat_new_stream) X(2, avformat_write_header) X(2, avio_alloc_context)  \
  X(2, avio_context_free) X(2, avio_flush)                                                                    \
  X(3, sws_freeContext) X(3, sws_getCoefficients) X(3, sws_getContext) X(3, sws_scale)                        \
  X(3, sws_setColorspaceDetails)
// clang-format on

struct LibAv {
#define DW_LIBAV_MEMBER(library, name) decltype(&::name) name = nullptr;
  DW_LIBAV_FUNCTIONS(DW_LIBAV_MEMBER)
#undef DW_LIBAV_MEMBER

  // The functions, or why they could not be loaded.
  static std::variant<std::unique_ptr<const LibAv>, std::string> open() {
    auto av = std::make_unique<LibAv>();
    const std::string libraries[] = {"libavutil.so." + std::to_string(LIBAVUTIL_VERSION_MAJOR),
                                     "libavcodec.so." + std::to_string(LIBAVCODEC_VERSION_MAJOR),
                                     "libavformat.so." + std::to_string(LIBAVFORMAT_VERSION_MAJOR),
                                     "libswscale.so." + std::to_string(LIBSWSCALE_VERSION_MAJOR)};
    for (size_t i = 0; i < av->handles_.size(); ++i) {
      av->handles_[i] = ::dlopen(libraries[i].c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
      if (!av->handles_[i]) return "videos need " + libraries[i] + ", which could not be loaded: " + ::dlerror();
    }
    std::string missing;
    const auto find = [&](auto& function, size_t library, const char* name) {
      function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(::dlsym(av->handles_[library], name));
      if (!function && missing.empty()) missing = libraries[library] + " lacks " + name;
    };
#define DW_LIBAV_FIND(library, name) find(av->name, library, #name);
    DW_LIBAV_FUNCTIONS(DW_LIBAV_FIND)
#undef DW_LIBAV_FIND
    if (!missing.empty()) return "videos need " + missing;
    return std::unique_ptr<const LibAv>(std::move(av));
  }
  ~LibAv() {
    for (void* handle : handles_)
      if (handle) ::dlclose(handle);
  }

 private:
  std::array<void*, 4> handles_{};  // avutil, avcodec, avformat, swscale
};

#undef DW_LIBAV_FUNCTIONS

std::string av_error(const LibAv& av, int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av.av_strerror(code, text, sizeof text);
  return text;
}

// Deleters of libav's objects, through the loaded functions.
struct CodecContextFree {
  const LibAv* av;
  void operator()(AVCodecContext* c) const { av->avcodec_free_context(&c); }
};
struct FormatContextFree {
  const LibAv* av;
  void operator()(AVFormatContext* c) const { av->avformat_free_context(c); }
};
struct IoContextFree {
  const LibAv* av;
  void operator()(AVIOContext* io) const {
    av->av_freep(&io->buffer);  // ours (avio_alloc_context's), possibly reallocated by libavformat
    av->avio_context_free(&io);
  }
};
struct FrameFree {
  const LibAv* av;
  void operator()(AVFrame* f) const { av->av_frame_free(&f); }
};
struct PacketFree {
  const LibAv* av;
  void operator()(AVPacket* p) const { av->av_packet_free(&p); }
};
struct ScalerFree {
  const LibAv* av;
  void operator()(SwsContext* s) const { av->sws_freeContext(s); }
};
struct DictionaryFree {
  const LibAv* av;
  void operator()(AVDictionary* d) const { av->av_dict_free(&d); }
};
struct FdClose {
  void operator()(const int* fd) const {
    ::close(*fd);
    delete fd;
  }
};

// Where the muxer writes. MP4 and WebM both go back to the start to fill in sizes, durations and
// indexes once the frames are known, which sim::OutputFile's stream cannot do (it writes forward
// only, to an unnamed temporary or a device). So the muxer writes to an unnamed scratch file
// (beside the target when the target is a regular file, on its file system; else in the
// temporary directory), which finish() copies into the output. Without a name it vanishes with
// the process, however that ends.
class ScratchFile {
 public:
  // The file, or the reason there is none.
  static std::variant<ScratchFile, std::string> create(const std::string& target) {
    struct stat st {};
    const bool regular_target = ::stat(target.c_str(), &st) != 0 || S_ISREG(st.st_mode);
    if (regular_target) {
      const std::string directory = std::filesystem::path(sim::resolved_path(target)).parent_path().string();
      const int fd = ::open(directory.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
      if (fd >= 0) return ScratchFile(fd);
    }
    // A file system without O_TMPFILE, or a target that is a device: a named file, unlinked at once.
    std::error_code ec;
    std::string name = (std::filesystem::temp_directory_path(ec) / "dwatch-video-XXXXXX").string();
    const int fd = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd < 0) return std::string("no scratch file for the video: ") + std::strerror(errno);
    ::unlink(name.c_str());
    return ScratchFile(fd);
  }

  int fd() const { return *fd_; }
  int error() const { return error_; }  // the first errno a write or seek met, or 0

  // AVIOContext callbacks (opaque: this).
  static int write(void* opaque, const uint8_t* bytes, int size) {
    auto* self = static_cast<ScratchFile*>(opaque);
    for (int done = 0; done < size;) {
      const ssize_t n = ::write(self->fd(), bytes + done, size_t(size - done));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) return self->failed(errno);
      done += int(n);
    }
    return size;
  }
  static int64_t seek(void* opaque, int64_t offset, int whence) {
    auto* self = static_cast<ScratchFile*>(opaque);
    if (whence & AVSEEK_SIZE) {
      struct stat st {};
      return ::fstat(self->fd(), &st) == 0 ? int64_t(st.st_size) : self->failed(errno);
    }
    const off_t at = ::lseek(self->fd(), off_t(offset), whence & ~AVSEEK_FORCE);
    return at < 0 ? self->failed(errno) : int64_t(at);
  }

 private:
  explicit ScratchFile(int fd) : fd_(new int(fd)) {}
  int failed(int code) {
    if (error_ == 0) error_ = code;
    return AVERROR(code);
  }

  std::unique_ptr<int, FdClose> fd_;
  int error_ = 0;
};

// avio_alloc_context's callback types differ across libavformat majors (const since 61).
#if LIBAVFORMAT_VERSION_MAJOR >= 61
int write_scratch(void* opaque, const uint8_t* bytes, int size) { return ScratchFile::write(opaque, bytes, size); }
#else
int write_scratch(void* opaque, uint8_t* bytes, int size) { return ScratchFile::write(opaque, bytes, size); }
#endif

const Format* format_of(const std::string& path, std::string& error) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  for (const Format& f : kFormats)
    if (extension == f.extension) return &f;
  error = path + ": a video's name ends in .mp4 (H.264) or .webm (VP9), not " +
          (extension.empty() ? std::string("nothing") : "'" + extension + "'");
  return nullptr;
}

std::string settings_problem(const VideoSettings& s) {
  if (s.width < 16 || s.width > 8192 || s.height < 16 || s.height > 8192)
    return "a video is 16 to 8192 pixels wide and high, not " + std::to_string(s.width) + "x" +
           std::to_string(s.height);
  if (s.width % 2 != 0 || s.height % 2 != 0)
    return "a video's width and height must be even (H.264 and VP9 keep colour at half resolution, yuv420p), not " +
           std::to_string(s.width) + "x" + std::to_string(s.height);
  if (s.fps < 1 || s.fps > 240) return "a video has 1 to 240 frames per second, not " + std::to_string(s.fps);
  return {};
}

}  // namespace

struct VideoWriter::Encoder {
  explicit Encoder(std::unique_ptr<const LibAv> functions)
      : libav(std::move(functions)),
        io(nullptr, {libav.get()}),
        muxer(nullptr, {libav.get()}),
        codec(nullptr, {libav.get()}),
        frame(nullptr, {libav.get()}),
        packet(nullptr, {libav.get()}),
        scaler(nullptr, {libav.get()}) {}

  // Freed in reverse: libav's functions after everything they free, the muxer before the I/O
  // context it writes through.
  std::unique_ptr<const LibAv> libav;
  const Format* format = nullptr;
  std::unique_ptr<sim::OutputFile> out;
  std::optional<ScratchFile> scratch;
  std::unique_ptr<AVIOContext, IoContextFree> io;
  std::unique_ptr<AVFormatContext, FormatContextFree> muxer;
  AVStream* stream = nullptr;  // the muxer's
  std::unique_ptr<AVCodecContext, CodecContextFree> codec;
  std::unique_ptr<AVFrame, FrameFree> frame;  // the yuv420p picture handed to the encoder
  std::unique_ptr<AVPacket, PacketFree> packet;
  std::unique_ptr<SwsContext, ScalerFree> scaler;  // RGBA -> yuv420p

  // What a failed write of the file says: the operating system's reason when there is one.
  std::string write_error(int code) const {
    const LibAv& av = *libav;
    const int os = scratch ? scratch->error() : 0;
    return "writing " + out->path() + " failed: " + (os != 0 ? std::strerror(os) : av_error(av, code));
  }

  // Hands `picture` (nullptr: the end) to the encoder and muxes every packet it has ready.
  std::string encode(const AVFrame* picture) {
    const LibAv& av = *libav;
    int result = av.avcodec_send_frame(codec.get(), picture);
    if (result < 0) return std::string(format->codec) + " encoder: " + av_error(av, result);
    for (;;) {
      result = av.avcodec_receive_packet(codec.get(), packet.get());
      if (result == AVERROR(EAGAIN) || result == AVERROR_EOF) return {};
      if (result < 0) return std::string(format->codec) + " encoder: " + av_error(av, result);
      // One frame long: x264 leaves the duration unset, and an MP4 whose last sample lasts no
      // time has it cut by players and decoders alike.
      if (packet->duration == 0) packet->duration = 1;
      av.av_packet_rescale_ts(packet.get(), codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      result = av.av_interleaved_write_frame(muxer.get(), packet.get());  // takes the packet's data
      if (result < 0) return write_error(result);
    }
  }
};

VideoWriter::VideoWriter(std::string path, std::unique_ptr<Encoder> encoder)
    : path_(std::move(path)), encoder_(std::move(encoder)) {}

VideoWriter::~VideoWriter() = default;

const char* VideoWriter::codec() const { return encoder_->format->codec; }

std::variant<std::unique_ptr<VideoWriter>, std::string> VideoWriter::open(const std::string& path,
                                                                          const VideoSettings& settings) {
  std::string error;
  const Format* format = format_of(path, error);
  if (!format) return error;
  if (error = settings_problem(settings); !error.empty()) return error;
  auto loaded = LibAv::open();
  if (auto* why = std::get_if<std::string>(&loaded)) return *why;
  auto e = std::make_unique<Encoder>(std::move(std::get<std::unique_ptr<const LibAv>>(loaded)));
  const LibAv& av = *e->libav;
  e->format = format;
  const AVCodec* codec = av.avcodec_find_encoder_by_name(e->format->encoder);
  if (!codec)
    return std::string("this libavcodec has no ") + e->format->encoder + " encoder, which " + e->format->extension +
           " (" + e->format->codec + ") needs: install Debian's libavcodec with " + e->format->package + ", or use " +
           (e->format == &kFormats[0] ? ".webm (VP9)" : ".mp4 (H.264)");

  e->out = sim::OutputFile::open(path, &error);
  if (!e->out) return error;
  auto scratch = ScratchFile::create(path);
  if (auto* problem = std::get_if<std::string>(&scratch)) return "cannot write " + path + ": " + *problem;
  e->scratch.emplace(std::move(std::get<ScratchFile>(scratch)));

  AVFormatContext* muxer = nullptr;
  if (int r = av.avformat_alloc_output_context2(&muxer, nullptr, e->format->muxer, nullptr); r < 0 || !muxer)
    return std::string("libavformat has no ") + e->format->muxer + " muxer: " + av_error(av, r);
  e->muxer.reset(muxer);

  e->codec.reset(av.avcodec_alloc_context3(codec));
  if (!e->codec) return "out of memory for the encoder";
  AVCodecContext& c = *e->codec;
  c.width = settings.width;
  c.height = settings.height;
  c.time_base = {1, settings.fps};
  c.framerate = {settings.fps, 1};
  c.pix_fmt = AV_PIX_FMT_YUV420P;
  c.gop_size = settings.fps * 5;  // a key frame every 5 s: a player seeks within a long video quickly
  c.thread_count = 0;             // as many as there are cores
  // The picture is sRGB, converted with BT.709's matrix to limited-range YUV below: say so, so
  // that players turn it back into the same colours.
  c.colorspace = AVCOL_SPC_BT709;
  c.color_primaries = AVCOL_PRI_BT709;
  c.color_trc = AVCOL_TRC_BT709;
  c.color_range = AVCOL_RANGE_MPEG;
  // libav's informational lines (x264's settings and statistics, libvpx's version) go a level
  // down, below what is printed; warnings and errors still show. Per context: no global level.
  c.log_level_offset = AV_LOG_VERBOSE - AV_LOG_INFO;
  if (e->muxer->oformat->flags & AVFMT_GLOBALHEADER) c.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  AVDictionary* options = nullptr;
  if (e->format == &kFormats[0]) {
    // Rendered pictures are flat colours and thin lines: constant quality 20 keeps the text and the
    // highlight's outline sharp; veryfast keeps 720p well ahead of the renderer on two cores.
    av.av_dict_set(&options, "preset", "veryfast", 0);
    av.av_dict_set(&options, "crf", "20", 0);
  } else {
    // libvpx's constant-quality mode (a crf with no bit-rate cap) at its real-time speed;
    // row-mt lets both cores work on one frame.
    c.bit_rate = 0;
    av.av_dict_set(&options, "crf", "30", 0);
    av.av_dict_set(&options, "deadline", "realtime", 0);
    av.av_dict_set(&options, "cpu-used", "8", 0);
    av.av_dict_set(&options, "row-mt", "1", 0);
  }
  std::unique_ptr<AVDictionary, DictionaryFree> left_over(nullptr, {&av});
  const int opened = av.avcodec_open2(&c, codec, &options);
  left_over.reset(options);
  if (opened < 0) return std::string("cannot open the ") + e->format->encoder + " encoder: " + av_error(av, opened);

  e->stream = av.avformat_new_stream(e->muxer.get(), nullptr);
  if (!e->stream) return "out of memory for the video stream";
  e->stream->time_base = c.time_base;
  if (int r = av.avcodec_parameters_from_context(e->stream->codecpar, &c); r < 0)
    return "cannot describe the video stream: " + av_error(av, r);

  constexpr int kIoBuffer = 1 << 16;
  auto* buffer = static_cast<unsigned char*>(av.av_malloc(kIoBuffer));
  if (!buffer) return "out of memory for the video's buffer";
  e->io.reset(av.avio_alloc_context(buffer, kIoBuffer, 1, &*e->scratch, nullptr, write_scratch, ScratchFile::seek));
  if (!e->io) {
    av.av_free(buffer);
    return "out of memory for the video's buffer";
  }
  e->muxer->pb = e->io.get();
  e->muxer->flags |= AVFMT_FLAG_CUSTOM_IO;
  if (int r = av.avformat_write_header(e->muxer.get(), nullptr); r < 0) return e->write_error(r);

  e->frame.reset(av.av_frame_alloc());
  e->packet.reset(av.av_packet_alloc());
  if (!e->frame || !e->packet) return "out of memory for a video frame";
  e->frame->format = c.pix_fmt;
  e->frame->width = c.width;
  e->frame->height = c.height;
  if (int r = av.av_frame_get_buffer(e->frame.get(), 0); r < 0)
    return "no memory for a video frame: " + av_error(av, r);

  e->scaler.reset(av.sws_getContext(c.width, c.height, AV_PIX_FMT_RGBA, c.width, c.height, AV_PIX_FMT_YUV420P,
                                    SWS_BILINEAR, nullptr, nullptr, nullptr));
  if (!e->scaler) return "cannot convert RGBA to yuv420p (libswscale)";
  const int* bt709 = av.sws_getCoefficients(SWS_CS_ITU709);
  av.sws_setColorspaceDetails(e->scaler.get(), bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);

  return std::unique_ptr<VideoWriter>(new VideoWriter(path, std::move(e)));
}

std::string VideoWriter::fail(std::string error) {
  error_ = std::move(error);
  return error_;
}

std::string VideoWriter::add_frame(const Image& frame) {
  if (!error_.empty()) return error_;
  if (finished_) return "the video " + path_ + " is finished: it takes no more frames";
  Encoder& e = *encoder_;
  const LibAv& av = *e.libav;
  if (frame.width != e.codec->width || frame.height != e.codec->height ||
      frame.rgba.size() != size_t(frame.width) * size_t(frame.height) * 4)
    return fail("frame " + std::to_string(frames_) + " is " + std::to_string(frame.width) + "x" +
                std::to_string(frame.height) + ", the video " + std::to_string(e.codec->width) + "x" +
                std::to_string(e.codec->height));
  // The encoder may still hold the last picture (its look-ahead): make_writable gives this one a
  // buffer of its own when it does.
  if (int r = av.av_frame_make_writable(e.frame.get()); r < 0)
    return fail("no memory for a video frame: " + av_error(av, r));
  const uint8_t* rows[1] = {frame.rgba.data()};
  const int stride[1] = {frame.width * 4};
  av.sws_scale(e.scaler.get(), rows, stride, 0, frame.height, e.frame->data, e.frame->linesize);
  e.frame->pts = frames_;
  if (std::string error = e.encode(e.frame.get()); !error.empty()) return fail(std::move(error));
  ++frames_;
  return {};
}

std::string VideoWriter::finish() {
  if (!error_.empty()) return error_;
  if (finished_) return {};
  // Neither container holds a video without frames (a player reads it as a broken file).
  if (frames_ == 0) return fail("the video " + path_ + " has no frames: nothing written");
  Encoder& e = *encoder_;
  const LibAv& av = *e.libav;
  if (std::string error = e.encode(nullptr); !error.empty()) return fail(std::move(error));
  if (int r = av.av_write_trailer(e.muxer.get()); r < 0) return fail(e.write_error(r));
  av.avio_flush(e.io.get());
  if (e.io->error < 0 || e.scratch->error() != 0) return fail(e.write_error(e.io->error));

  // The scratch file into the output, from its start.
  std::vector<char> chunk(size_t{1} << 20);
  std::ostream& out = e.out->stream();
  for (off_t at = 0;;) {
    const ssize_t n = ::pread(e.scratch->fd(), chunk.data(), chunk.size(), at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return fail("reading the video back from its scratch file failed: " + std::string(std::strerror(errno)));
    if (n == 0) break;
    out.write(chunk.data(), std::streamsize(n));
    at += n;
  }
  if (std::string error = e.out->commit(); !error.empty()) return fail(std::move(error));
  finished_ = true;
  return {};
}

}  // namespace dw::render
