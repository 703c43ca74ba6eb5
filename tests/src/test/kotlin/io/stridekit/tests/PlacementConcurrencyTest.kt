package io.stridekit.tests

import io.stridekit.PlacementClassifier
import io.stridekit.android.common.AccelBatcher
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicLong
import kotlin.math.PI
import kotlin.math.sin
import kotlin.test.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertNotNull
import kotlin.test.assertTrue

/**
 * Four threads pushing packed accelerometer batches (written by the Android adapters'
 * AccelBatcher) into one PlacementClassifier: no crash, every sample accepted or
 * rejected, consistent state. Compiled only when the bindings have the classifier
 * (it used to be behind a Maven profile; the classifier is always there now).
 */
class PlacementConcurrencyTest {
    @Test
    fun `four threads pushing into one placement classifier`() {
        val block = 50
        val clock = AtomicLong(0)
        val pushed = AtomicInteger()
        val rejected = AtomicInteger()
        val unexpected = AtomicInteger()
        val start = CountDownLatch(1)
        val pool = Executors.newFixedThreadPool(4)
        PlacementClassifier.withDefaults().use { c ->
            repeat(4) { k ->
                pool.execute {
                    start.await()
                    try {
                        for (i in 0 until 100) {
                            val first = clock.getAndAdd(block.toLong())
                            val batch = AccelBatcher()
                            for (j in 0 until block) {
                                val t = (first + j) / 100.0 // 100 Hz, walking-like bounce
                                batch.add(t, 0.5, 0.3 * sin(2 * PI * 1.8 * t), 9.81 + 2.0 * sin(2 * PI * 1.8 * t))
                            }
                            val r = c.pushAccelPacked(batch.buffer.drain())
                            pushed.addAndGet(block)
                            rejected.addAndGet(r.rejected.size)
                            if (k == 2 && i % 25 == 5) PlacementClassifier.restore(c.snapshot()).close()
                            c.estimate()
                        }
                    } catch (e: Throwable) {
                        unexpected.incrementAndGet()
                        e.printStackTrace()
                    }
                }
            }
            start.countDown()
            pool.shutdown()
            assertTrue(pool.awaitTermination(120, TimeUnit.SECONDS), "threads finished")
            assertEquals(0, unexpected.get(), "unexpected exceptions")
            assertEquals(20_000, pushed.get())
            assertTrue(rejected.get() < pushed.get() * 3 / 4, "rejected ${rejected.get()} of ${pushed.get()}")
            // Accepted samples span well over one 5.12 s window: an estimate exists.
            val e = assertNotNull(c.estimate())
            assertTrue(e.windows > 0L)
            val saved = c.snapshot()
            PlacementClassifier.restore(saved).use { assertContentEquals(saved, it.snapshot()); assertEquals(c.estimate(), it.estimate()) }
        }
    }
}
