; a1
(grasp p1 knife)
(cut p1 knife tomato)
(release p1 knife)
; a2
(grasp p1 chopping_board)
(transfer p1 chopping_board tomato chopping_board pot)
(release p1 chopping_board)
; a3
(grasp p1 spoon)
(handover p1 p2 spoon)
(release p2 spoon)
; a4
(grasp p1 pot)
(hold-steady p1 pot)
(grasp p2 spoon)
(stir p2 spoon pot)
(release p2 spoon)
(release p1 pot)
; a5
(transfer-by-hand p2 onion bowl_2 pot)
; a6
(grasp p2 whisk)
(stir p2 whisk onion)
(stir p2 whisk tomato)
(release p2 whisk)
