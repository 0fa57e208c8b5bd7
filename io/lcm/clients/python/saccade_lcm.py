"""Saccade's messages in Python without LCM's Python binding (Debian ships none).

Receiver joins LCM's UDP multicast group as liblcm does and yields (channel, data) for each
whole message, fragmented ones put back together; read_log yields the events of an lcm-logger
file. Decode data with the lcm-gen types installed beside this module:

    from saccade import detections_t
    from saccade_lcm import Receiver
    for channel, data in Receiver().messages({"SACCADE_DETECTIONS"}):
        d = detections_t.decode(data)

Sender publishes one (a command: sign it with the key first, docs/LCM.md "Signed commands"):

    Sender().publish("SACCADE_COMMAND", sign(command.encode(), read_key("command.key")))
"""
import hashlib
import hmac
import socket
import struct
import urllib.parse

DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=0"
_SHORT = 0x4C433032  # "LC02": a whole message in one datagram
_FRAGMENT = 0x4C433033  # "LC03": one fragment of a larger message
_LOG_SYNC = 0xEDA1DA01


class Receiver:
    """Subscribes to an udpm:// LCM network (the default is saccaded's)."""

    def __init__(self, url=DEFAULT_URL):
        group, port, _ = _group(url)
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self._sock.bind(("", port))
        membership = struct.pack("4s4s", socket.inet_aton(group),
                                 socket.inet_aton("0.0.0.0"))
        self._sock.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, membership)
        self._partial = {}  # (sender, sequence) -> [channel, buffer, fragments left]

    def messages(self, channels=None, timeout=None):
        """Yields (channel, data) for messages on `channels` (all when None); stops after
        `timeout` seconds without a datagram (never when None)."""
        self._sock.settimeout(timeout)
        while True:
            try:
                packet, sender = self._sock.recvfrom(65536)
            except socket.timeout:
                return
            whole = self._take(packet, sender)
            if whole and (channels is None or whole[0] in channels):
                yield whole

    def _take(self, packet, sender):
        if len(packet) < 8:
            return None
        magic, sequence = struct.unpack(">II", packet[:8])
        if magic == _SHORT:
            end = packet.find(b"\0", 8)
            return None if end < 0 else (packet[8:end].decode(), packet[end + 1:])
        if magic != _FRAGMENT or len(packet) < 20:
            return None
        size, offset, number, count = struct.unpack(">IIHH", packet[8:20])
        body, key = packet[20:], (sender, sequence)
        if number == 0:
            end = body.find(b"\0")
            if end < 0:
                return None
            self._partial[key] = [body[:end].decode(), bytearray(size), count]
            body = body[end + 1:]
        entry = self._partial.get(key)
        if entry is None or offset + len(body) > size:
            return None
        entry[1][offset:offset + len(body)] = body
        entry[2] -= 1
        if entry[2] > 0:
            return None
        del self._partial[key]
        return entry[0], bytes(entry[1])


def _group(url):
    parsed = urllib.parse.urlparse(url)
    if parsed.scheme != "udpm" or not parsed.hostname or not parsed.port:
        raise ValueError("not an udpm://GROUP:PORT LCM url: %r" % url)
    ttl = int(urllib.parse.parse_qs(parsed.query).get("ttl", ["0"])[0])
    return parsed.hostname, parsed.port, ttl


class Sender:
    """Publishes whole messages of up to 64 KB on an udpm:// LCM network, as liblcm does."""

    def __init__(self, url=DEFAULT_URL):
        self._group, self._port, ttl = _group(url)
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        self._sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, ttl)
        self._sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
        self._sequence = 0

    def publish(self, channel, data):
        packet = struct.pack(">II", _SHORT, self._sequence) + channel.encode() + b"\0" + data
        if len(packet) > 65507:
            raise ValueError("a message of %d bytes needs LCM's fragments" % len(data))
        self._sequence += 1
        self._sock.sendto(packet, (self._group, self._port))


def read_key(path):
    """The 32-byte command key of a file saccade keygen wrote (64 hexadecimal digits)."""
    with open(path) as f:
        key = bytes.fromhex(f.read().strip())
    if len(key) != 32:
        raise ValueError("%s: not a command key (64 hexadecimal digits)" % path)
    return key


def sign(encoded, key):
    """An encoded command_t with its last 32 bytes (the signature) the HMAC-SHA256, with `key`,
    of every byte before them."""
    body = encoded[:-32]
    return body + hmac.new(key, body, hashlib.sha256).digest()


def read_log(path):
    """Yields (channel, data, utime) for each event of an lcm-logger file."""
    with open(path, "rb") as log:
        while True:
            header = log.read(28)
            if len(header) < 28:
                return
            sync, _, utime, channel_len, data_len = struct.unpack(">IqqII", header)
            if sync != _LOG_SYNC:
                raise ValueError("%s: not an lcm-logger event at byte %d" % (path, log.tell() - 28))
            channel = log.read(channel_len).decode()
            data = log.read(data_len)
            if len(data) < data_len:
                return  # the last event cut short
            yield channel, data, utime
