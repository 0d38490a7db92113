// SpyDecode - roadscan's messages through lcm-spy's own decoding path: the
// spy's type database (lcm.spy.LCMTypeDatabase, which scans the class path for
// LCM types) finds each message's class by its fingerprint, and the class
// decodes it, as the spy does before showing it. Reads an LCM log; prints, per
// channel, the class and the number of messages decoded, then one decoded
// object list's fields. Run by tests/java_types.sh:
//   java -cp lcm.jar:roadscan-lcmtypes.jar:DIR SpyDecode LOG
import java.io.ByteArrayInputStream;
import java.io.DataInputStream;
import java.io.EOFException;
import java.util.TreeMap;

public class SpyDecode {
  public static void main(String[] args) throws Exception {
    lcm.spy.LCMTypeDatabase db = new lcm.spy.LCMTypeDatabase();
    lcm.logging.Log log = new lcm.logging.Log(args[0], "r");
    TreeMap<String, Integer> counts = new TreeMap<>();
    String sample = null;
    int unknown = 0;
    for (;;) {
      lcm.logging.Log.Event ev;
      try {
        ev = log.readNext();
      } catch (EOFException e) {
        break;
      }
      DataInputStream in = new DataInputStream(new ByteArrayInputStream(ev.data));
      long fingerprint = in.readLong();
      Class<?> cls = db.getClassByFingerprint(fingerprint);
      if (cls == null) {
        unknown++;
        continue;
      }
      Object msg = cls.getConstructor(byte[].class).newInstance(ev.data);
      counts.merge(ev.channel + " " + cls.getName(), 1, Integer::sum);
      if (sample == null && msg instanceof roadscan.object_list_t) {
        roadscan.object_list_t l = (roadscan.object_list_t) msg;
        sample = "sample " + l.sensor_id + " frame " + l.frame_seq + " objects " + l.num_objects;
      }
    }
    for (java.util.Map.Entry<String, Integer> e : counts.entrySet())
      System.out.println(e.getKey() + " " + e.getValue());
    System.out.println("unknown " + unknown);
    if (sample != null) System.out.println(sample);
  }
}
