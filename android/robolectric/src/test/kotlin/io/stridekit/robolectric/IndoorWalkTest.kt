package io.stridekit.robolectric

import android.content.Context
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Bundle
import android.os.Parcel
import io.stridekit.NavEstimate
import io.stridekit.NavStep
import io.stridekit.PhoneNavigator
import io.stridekit.android.StrideSensors
import io.stridekit.android.common.NavigatorSession
import io.stridekit.android.common.SessionState
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.Job
import kotlinx.coroutines.cancel
import kotlinx.coroutines.launch
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowSensor
import java.io.File
import kotlin.math.abs

/**
 * A real indoor walk (../shared/data/phone-indoor) replayed as Android delivers it:
 * SensorEvents of the accelerometer, gyroscope and magnetometer, one per logged line
 * in the log's order and at its times (`timestamp` = the logged ms × 10⁶), through
 * the shadow SensorManager into StrideSensors and a NavigatorSession. The steps and
 * estimates the session publishes must be what `stridekit pdr FILE` writes for the
 * same file.
 */
@RunWith(RobolectricTestRunner::class)
@Config(sdk = [35])
class IndoorWalkTest {
    private val context: Context get() = RuntimeEnvironment.getApplication()

    /** A log line as a sensor event: Android type, time (ns), the three Float values. */
    private class Line(val type: Int, val ns: Long, val values: FloatArray, val accuracy: Int)

    private fun events(log: File): List<Line> = Shared.lines(log).mapNotNull { line ->
        val f = line.trim().split(Regex("\\s+"))
        val type = when (f.getOrNull(1)) {
            "TYPE_ACCELEROMETER" -> Sensor.TYPE_ACCELEROMETER
            "TYPE_GYROSCOPE" -> Sensor.TYPE_GYROSCOPE
            "TYPE_MAGNETIC_FIELD" -> Sensor.TYPE_MAGNETIC_FIELD
            else -> return@mapNotNull null
        }
        // SensorEvent.values are Floats: the log printed them with Float.toString.
        Line(type, f[0].toLong() * 1_000_000L, floatArrayOf(f[2].toFloat(), f[3].toFloat(), f[4].toFloat()), f.getOrNull(5)?.toIntOrNull() ?: 3)
    }

    /** What a running app has: the sensors, its session and what it collected. */
    private inner class App(val session: NavigatorSession) {
        val sensorManager = context.getSystemService(Context.SENSOR_SERVICE) as SensorManager
        val sensors = StrideSensors(sensorManager, session)
        val steps = mutableListOf<NavStep>()
        val estimates = mutableListOf<NavEstimate>()
        private val scope = CoroutineScope(Dispatchers.Unconfined + Job())

        init {
            // Collectors on the emitting thread: nothing is dropped, nothing races.
            scope.launch { session.steps.collect { steps += it } }
            scope.launch { session.estimates.collect { estimates += it } }
            val types = intArrayOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE, Sensor.TYPE_MAGNETIC_FIELD)
            val registered = sensors.start(*types, samplingPeriodUs = 20_000)
            assertEquals(types.toList(), registered)
        }

        fun deliver(lines: List<Line>) {
            val shadow = shadowOf(sensorManager)
            for (l in lines) {
                val e = SensorEventBuilder.newBuilder()
                    .setSensor(sensorManager.getDefaultSensor(l.type)!!)
                    .setTimestamp(l.ns)
                    .setValues(l.values)
                    .setAccuracy(l.accuracy)
                    .build()
                shadow.sendSensorEventToListeners(e)
            }
        }

        /** The sensors stop: the session finishes; returns its final estimate. */
        fun stop(): NavEstimate? {
            kill()
            return session.finish().also { scope.cancel() }
        }

        /** The process dies: the sensors and the collectors go, nothing is finished. */
        fun kill() {
            sensors.stop()
            assertFalse("listeners unregistered on stop", shadowOf(sensorManager).hasListener(sensors))
        }
    }

    private fun addSensors() {
        val sm = context.getSystemService(Context.SENSOR_SERVICE) as SensorManager
        for (t in intArrayOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE, Sensor.TYPE_MAGNETIC_FIELD)) {
            shadowOf(sm).addSensor(ShadowSensor.newInstance(t))
        }
    }

    /** Two walks of different floors (short and long), the first of their folders. */
    private fun logs(): List<File> {
        val dir = Shared.folder("phone-indoor/site1")
        return listOf("B1", "F3").map { floor ->
            dir.resolve(floor).listFiles { f -> f.name.endsWith(".txt.gz") }!!.minBy { it.name }
        }
    }

    /** The CLI's trajectory of a log: one row per step. */
    private fun cliSteps(log: File): List<Map<String, String>> {
        val out = Shared.tempDir("pdr").resolve("${log.name}.csv")
        Shared.run("pdr", log.path, "--out", out.path)
        return Shared.csv(out)
    }

    /** The steps equal the CLI's rows at the CSV's printed precision, row for row. */
    private fun assertSameSteps(log: File, expected: List<Map<String, String>>, got: List<NavStep>) {
        assertEquals("${log.name}: steps", expected.size, got.size)
        for ((i, pair) in expected.zip(got).withIndex()) {
            val (row, s) = pair
            val mine = listOf(
                Shared.fmt(s.tS, 3), Shared.fmt(s.eastM, 3), Shared.fmt(s.northM, 3), Shared.fmt(s.lengthM, 3),
                Shared.fmt(Math.toDegrees(s.azimuthRad), 1), (i + 1).toString(),
            )
            val cli = listOf("t_s", "east_m", "north_m", "step_length_m", "azimuth_deg", "steps").map { row.getValue(it) }
            assertEquals("${log.name}: step ${i + 1}", cli, mine)
        }
    }

    @Test
    fun `a real indoor walk through SensorManager gives what stridekit pdr gives`() {
        addSensors()
        for (log in logs()) {
            val expected = cliSteps(log)
            val lines = events(log)
            PhoneNavigator.withDefaults().use { nav ->
                val app = App(NavigatorSession(nav))
                app.deliver(lines)
                val final = app.stop()!!
                assertSameSteps(log, expected, app.steps)
                // The Flow of estimates: each at a step's position (or the start), in
                // the track's order; the last one where the CLI's track ends.
                val rows = expected.map { Shared.fmt(it.getValue("east_m").toDouble(), 3) to Shared.fmt(it.getValue("north_m").toDouble(), 3) }
                var k = -1
                for (e in app.estimates) {
                    val p = Shared.fmt(e.eastM, 3) to Shared.fmt(e.northM, 3)
                    if (p == Shared.fmt(0.0, 3) to Shared.fmt(0.0, 3) && k < 0) continue
                    val at = (maxOf(k, 0) until rows.size).firstOrNull { rows[it] == p }
                    assertTrue("${log.name}: estimate at $p is on the CLI's track after row $k", at != null)
                    k = at!!
                }
                assertEquals(final, app.estimates.last())
                assertEquals(rows.last(), Shared.fmt(final.eastM, 3) to Shared.fmt(final.northM, 3))
                assertEquals(expected.size.toLong(), final.steps)
                val counts = nav.sensorEventCounts()
                assertEquals(lines.count { it.type == Sensor.TYPE_ACCELEROMETER }.toLong(), counts.samples)
                assertEquals(0L, counts.withoutGyro + counts.overflow + counts.refused)
            }
        }
    }

    @Test
    fun `a session saved in onSaveInstanceState and restored after the process is killed ends where the unbroken one does`() {
        addSensors()
        val log = logs().last()
        val lines = events(log)
        val unbroken = PhoneNavigator.withDefaults().use { nav ->
            val app = App(NavigatorSession(nav))
            app.deliver(lines)
            app.stop()!! to app.steps.toList()
        }
        for (split in listOf(lines.size / 3, lines.size / 2 + 1)) {
            // Until onSaveInstanceState: the state goes into the Bundle.
            val outState = Bundle()
            val before = PhoneNavigator.withDefaults().use { nav ->
                val app = App(NavigatorSession(nav, maxBatch = 100))
                app.deliver(lines.subList(0, split))
                outState.putByteArray(STATE_KEY, app.session.saveState().toBytes())
                app.kill()
                app.steps.toList()
            }
            // The process is killed: only the parcelled Bundle survives.
            val parcel = Parcel.obtain()
            outState.writeToParcel(parcel, 0)
            val bytes = parcel.marshall()
            parcel.recycle()
            val revived = Parcel.obtain()
            revived.unmarshall(bytes, 0, bytes.size)
            revived.setDataPosition(0)
            val savedInstanceState = Bundle.CREATOR.createFromParcel(revived)
            revived.recycle()
            // onCreate(savedInstanceState): the session continues.
            val state = SessionState.fromBytes(savedInstanceState.getByteArray(STATE_KEY)!!)
            val restored = NavigatorSession.restore(state)
            restored.navigator.use {
                val app = App(restored)
                app.deliver(lines.subList(split, lines.size))
                val final = app.stop()!!
                assertEquals("split at $split", unbroken.first, final)
                assertEquals("split at $split", unbroken.second, before + app.steps)
            }
        }
    }

    private companion object {
        const val STATE_KEY = "stridekit.navigator"
    }
}
