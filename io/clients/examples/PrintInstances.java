// Prints where saccaded sees each instance: java PrintInstances [URL] [FRAMES]
import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;
import saccade.detections_t;
import saccade.instance_t;
import java.util.concurrent.CountDownLatch;

public class PrintInstances {
  public static void main(String[] args) throws Exception {
    LCM lcm = new LCM(args.length > 0 ? args[0] : "udpm://239.255.76.67:7667?ttl=0");
    int frames = args.length > 1 ? Integer.parseInt(args[1]) : 0;  // 0: until Ctrl-C
    CountDownLatch left = new CountDownLatch(frames > 0 ? frames : 1);
    lcm.subscribe("SACCADE_DETECTIONS", (LCM l, String channel, LCMDataInputStream in) -> {
      try {
        detections_t d = new detections_t(in);
        for (instance_t i : d.instances)  // centroid: where the object is
          System.out.printf("%s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f%n", i.model_name,
                            i.centroid[0], i.centroid[1], i.centroid[2], d.frame, i.confidence);
        if (d.num_instances > 0 && frames > 0) left.countDown();
      } catch (java.io.IOException e) { System.err.println("malformed: " + e.getMessage()); }
    });
    left.await();  // LCM delivers on its own thread; with FRAMES 0 this never returns
    System.exit(0);
  }
}
