// Prints where saccaded sees each instance, and each track's state changes:
// java PrintInstances [URL] [FRAMES]. Act on TRACKING and RE-ACQUIRED only (docs/LCM.md).
import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;
import saccade.detections_t;
import saccade.instance_t;
import java.util.HashMap;
import java.util.Map;
import java.util.concurrent.CountDownLatch;

public class PrintInstances {
  // mug for /var/lib/saccade/models/mug.pcd; a spec such as synthetic:target as it is.
  static String shortName(String modelName) {
    String name = modelName.substring(modelName.lastIndexOf('/') + 1);
    int dot = name.lastIndexOf('.');
    if (dot > 0) name = name.substring(0, dot);
    return name.isEmpty() ? modelName : name;
  }

  public static void main(String[] args) throws Exception {
    LCM lcm = new LCM(args.length > 0 ? args[0] : "udpm://239.255.76.67:7667?ttl=0");
    int frames = args.length > 1 ? Integer.parseInt(args[1]) : 0;  // 0: until Ctrl-C
    CountDownLatch left = new CountDownLatch(frames > 0 ? frames : 1);
    Map<Integer, String> states = new HashMap<>();  // track id -> its last state
    lcm.subscribe("SACCADE_DETECTIONS", (LCM l, String channel, LCMDataInputStream in) -> {
      try {
        detections_t d = new detections_t(in);
        for (instance_t i : d.instances) {
          String name = shortName(i.model_name);
          String last = states.get(i.track_id);
          if (i.track_id >= 0 && !i.track_state_name.equals(last)) {
            System.out.printf("%s #%d: %s -> %s%n", name, i.track_id, last == null ? "NEW" : last,
                              i.track_state_name);
            states.put(i.track_id, i.track_state_name);
          }
          // centroid: where the object is (trans is the model's origin)
          System.out.printf("%s #%d %s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f%n", name,
                            i.track_id, i.track_state_name, i.centroid[0], i.centroid[1],
                            i.centroid[2], d.frame, i.confidence);
        }
        System.out.flush();
        if (d.num_instances > 0 && frames > 0) left.countDown();
      } catch (java.io.IOException e) { System.err.println("malformed: " + e.getMessage()); }
    });
    left.await();  // LCM delivers on its own thread; with FRAMES 0 this never returns
    System.exit(0);
  }
}
