// Sends saccaded one signed command:
// java SendCommand URL KEY_FILE pause|resume|reset|fovea X Y Z (docs/LCM.md, "Signed commands").
// HMAC-SHA256 with the key of KEY_FILE over every byte of the encoded command_t before its last
// 32, which it fills.
import java.io.ByteArrayOutputStream;
import java.io.DataOutputStream;
import java.nio.file.Files;
import java.nio.file.Paths;
import javax.crypto.Mac;
import javax.crypto.spec.SecretKeySpec;
import lcm.lcm.LCM;
import saccade.command_t;

public class SendCommand {
  public static void main(String[] args) throws Exception {
    if (args.length < 3) {
      System.err.println("usage: java SendCommand URL KEY_FILE pause|resume|reset|fovea X Y Z");
      System.exit(2);
    }
    String hex = new String(Files.readAllBytes(Paths.get(args[1]))).trim();
    if (hex.length() != 64)
      throw new IllegalArgumentException(args[1] + ": not a command key");
    byte[] key = new byte[32];
    for (int i = 0; i < 32; ++i)
      key[i] = (byte) Integer.parseInt(hex.substring(2 * i, 2 * i + 2), 16);

    command_t m = new command_t();
    m.utime = System.currentTimeMillis() * 1000;
    m.sequence = 0; // a program sending several commands counts them: 0, 1, 2, ...
    m.model = "";
    switch (args[2]) {
      case "pause":
        m.kind = command_t.PAUSE;
        break;
      case "resume":
        m.kind = command_t.RESUME;
        break;
      case "reset":
        m.kind = command_t.RESET;
        break;
      case "fovea":
        m.kind = command_t.SET_FOVEA;
        for (int i = 0; i < 3; ++i) m.fovea[i] = Double.parseDouble(args[3 + i]);
        break;
      default:
        throw new IllegalArgumentException("unknown command " + args[2]);
    }
    ByteArrayOutputStream buffer = new ByteArrayOutputStream();
    m.encode(new DataOutputStream(buffer));
    byte[] bytes = buffer.toByteArray();
    Mac hmac = Mac.getInstance("HmacSHA256");
    hmac.init(new SecretKeySpec(key, "HmacSHA256"));
    hmac.update(bytes, 0, bytes.length - 32);
    System.arraycopy(hmac.doFinal(), 0, bytes, bytes.length - 32, 32);
    LCM lcm = new LCM(args[0]);
    lcm.publish("SACCADE_COMMAND", bytes, 0, bytes.length);
    lcm.close();
    System.out.println("sent " + args[2] + ", signed");
  }
}
