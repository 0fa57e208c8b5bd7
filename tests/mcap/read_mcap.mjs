// Reads an MCAP file with Foxglove's own readers (@mcap/core, @foxglove/rosmsg,
// @foxglove/rosmsg2-serialization; none of Saccade's code): every message decoded through the
// ros2msg schema its channel names. Prints one JSON object: the profile, per topic the schema
// and the count, the messages that failed to decode, and each message decoded (compact), for
// the test to compare with the LCM log it came from.
//   node read_mcap.mjs FILE.mcap
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { decompress } from "fzstd";
import { open } from "node:fs/promises";

const path = process.argv[2];
const handle = await open(path, "r");
const readable = {
  size: async () => BigInt((await handle.stat()).size),
  read: async (offset, length) => {
    const buffer = new Uint8Array(Number(length));
    await handle.read(buffer, 0, Number(length), Number(offset));
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({
  readable,
  decompressHandlers: { zstd: (data, size) => decompress(data, new Uint8Array(Number(size))) },
});
const readers = new Map();
for (const [id, schema] of reader.schemasById) {
  if (schema.encoding !== "ros2msg") throw new Error(`schema ${schema.name}: ${schema.encoding}`);
  const text = new TextDecoder().decode(schema.data);
  readers.set(id, new MessageReader(parse(text, { ros2: true })));
}
const topics = {};
let failed = 0;
const messages = [];
for await (const m of reader.readMessages()) {
  const channel = reader.channelsById.get(m.channelId);
  const schema = reader.schemasById.get(channel.schemaId);
  const t = (topics[channel.topic] ??= { schema: schema.name, encoding: channel.messageEncoding, count: 0 });
  t.count++;
  try {
    const decoded = readers.get(channel.schemaId).readMessage(m.data);
    if (schema.name === "sensor_msgs/msg/CompressedImage") decoded.data = decoded.data.length;
    if (schema.name === "sensor_msgs/msg/PointCloud2") {
      // The points' z (metres, by the field named z), then only the data's length.
      const z = decoded.fields.find((f) => f.name === "z");
      const view = new DataView(decoded.data.buffer, decoded.data.byteOffset, decoded.data.byteLength);
      decoded.z = [];
      for (let i = 0; i < decoded.width; i++)
        decoded.z.push(view.getFloat32(i * decoded.point_step + z.offset, !decoded.is_bigendian));
      decoded.data = decoded.data.length;
    }
    messages.push({ topic: channel.topic, log_time: m.logTime.toString(), message: decoded });
  } catch (e) {
    failed++;
  }
}
await handle.close();
const out = {
  profile: reader.header.profile,
  library: reader.header.library,
  message_count: Number(reader.statistics?.messageCount ?? -1),
  topics,
  failed,
  messages,
};
const plain = (k, v) =>
  typeof v === "bigint" ? v.toString() : ArrayBuffer.isView(v) ? Array.from(v) : v;
process.stdout.write(JSON.stringify(out, plain) + "\n");
