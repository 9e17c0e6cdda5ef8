/* SPDX-License-Identifier: BSD-3-Clause */
// JavaRoundTrip: the Java side of test_msg_python.py. Reads lines
// "<type> <hex datagram>" on stdin; for each, decodes the datagram with the
// generated class kinctl.<type> from kinctl_lcmtypes.jar (the classes lcm-spy
// uses) and prints the hex of its re-encoding, so the test can require the
// same bytes back.
import java.io.BufferedReader;
import java.io.ByteArrayOutputStream;
import java.io.DataOutputStream;
import java.io.InputStreamReader;

public class JavaRoundTrip {
    public static void main(String[] args) throws Exception {
        BufferedReader in = new BufferedReader(new InputStreamReader(System.in));
        String line;
        while ((line = in.readLine()) != null) {
            String[] f = line.trim().split(" ");
            byte[] data = new byte[f[1].length() / 2];
            for (int i = 0; i < data.length; i++)
                data[i] = (byte) Integer.parseInt(f[1].substring(2 * i, 2 * i + 2), 16);
            Class<?> c = Class.forName("kinctl." + f[0]);
            lcm.lcm.LCMEncodable m =
                (lcm.lcm.LCMEncodable) c.getConstructor(byte[].class).newInstance((Object) data);
            ByteArrayOutputStream bos = new ByteArrayOutputStream();
            m.encode(new DataOutputStream(bos));
            StringBuilder sb = new StringBuilder();
            for (byte b : bos.toByteArray())
                sb.append(String.format("%02x", b & 0xff));
            System.out.println(f[0] + " " + sb);
        }
    }
}
